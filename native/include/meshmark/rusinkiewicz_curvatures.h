// meshmark: principal curvatures per vertex by Rusinkiewicz's per-face tensor estimate, as Itzik Ben Shabat's
// MATLAB GetCurvatures (FileExchange 47134, July 2014) computes them; the curvature estimator of the
// published LFS76 code (GetCurvInfo.m; docs/steganalysis.md §3).
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

struct PrincipalCurvatures {
  Eigen::VectorXd k1, k2;  // (n,) |k1| >= |k2|; 0, 0 for a vertex in no face; NaN propagates from degenerate rings
};

// S. Rusinkiewicz, "Estimating curvatures and their derivatives on triangle meshes", 3DPVT 2004, in Ben
// Shabat's form: unit face normals cross(v2 - v1, v0 - v2); vertex normals weighted by Max (1999),
// area / (|e_a|^2 |e_b|^2) of the two edges at the corner (Heron's area; a face whose Heron product
// rounds below zero, which MATLAB makes imaginary, weighs 0); Meyer et al.'s mixed Voronoi corner areas; a
// 6 x 3 least-squares fit of each face's second fundamental form to the normal differences along its
// edges (frame t = normalised v2 - v1, B = n x t); the face tensors rotated into each corner's vertex frame
// (up = the corner's edge of the last face listing the vertex, crossed with the vertex normal) and summed
// with weights corner area / vertex area; k1, k2 from one Jacobi rotation (trimesh2).
PrincipalCurvatures rusinkiewicz_curvatures(const Eigen::Ref<const MatrixX3dR>& X, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
