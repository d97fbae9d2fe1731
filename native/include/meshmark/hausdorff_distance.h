// meshmark: one-sided Hausdorff distance between triangle meshes with a guaranteed error bound.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct HausdorffBound {
  double lower = 0;  // attained: the distance of an actual point of A to B
  double upper = 0;  // no point of A is farther than this from B
  Eigen::Index n_queries = 0;
};

// h(A -> B) = max over the surface A of the distance to the surface B, by branch and bound:
// every triangle of A starts with the exact distances of its corners and centroid; a triangle's
// bound is min(d(c) + max|v - c|, min_i (d(v_i) + max_j |v_j - v_i|)) (the distance to B is
// 1-Lipschitz); the triangle with the largest bound is split 1-to-4 at its edge midpoints until
// upper <= lower * (1 + rel_tol) + abs_tol. Unlike Metro's sampling, the maximum inside large
// triangles (a simplified mesh against its original) is not missed. Unreferenced vertices of A
// take no part.
HausdorffBound hausdorff_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                  const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                  double rel_tol = 1e-3, double abs_tol = 0.0);

}  // namespace meshmark
