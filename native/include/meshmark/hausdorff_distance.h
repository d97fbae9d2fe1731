// meshmark: one-sided Hausdorff distance between triangle meshes with a guaranteed error bound.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct HausdorffBound {
  double lower = 0;  // attained: the distance of an actual point of A to B
  double upper = 0;  // no point of A is farther than this from B
  Eigen::Index n_queries = 0;
  bool converged = true;  // false: the query budget ran out before upper <= lower (1 + rel_tol) + abs_tol
};

// h(A -> B) = max over the surface A of the distance to the surface B, by branch and bound:
// every triangle of A starts with the exact distances of its corners and centroid; a cell's bound is
// the smallest of the Lipschitz bounds d(q) + max |v - q| (q the centroid or a corner), of
// max_i d(v_i, T) over the nearest triangles T of its corners and centroid (the distance to one
// triangle is convex), and, for two of them that share an edge, of the same bound on the two pieces
// the plane bisecting their dihedral angle cuts from the cell (a cell straddling an edge of B, where
// A lies on or near B, is then not split down to the size of the distance). The cell with the largest bound is
// split 1-to-4 at its edge midpoints until upper <= lower * (1 + rel_tol) + abs_tol, or until
// `max_queries` point-to-mesh distance queries have been made (then `converged` is false and
// [lower, upper] is the bound reached; max_queries <= 0: no limit). Unlike Metro's sampling, the
// maximum inside large triangles (a simplified mesh against its original) is not missed.
// Unreferenced vertices of A take no part.
HausdorffBound hausdorff_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                  const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                  double rel_tol = 1e-3, double abs_tol = 0.0, Eigen::Index max_queries = 0);

}  // namespace meshmark
