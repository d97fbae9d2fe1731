// meshmark: Metro-style surface distances between two triangle meshes.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

// n points uniformly distributed by area on the triangles (V, T), drawn with Rng(seed): per sample,
// u ~ uniform01 picks the triangle by inverse CDF of the cumulated areas, then r1, r2 ~ uniform01
// (reflected to r1 + r2 <= 1 when their sum exceeds 1) give p = a + r1 (b - a) + r2 (c - a).
// Samples are returned grouped by triangle, in triangle order. face: (n,) source triangle.
MatrixX3dR sample_surface(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                          Eigen::Index n, std::uint64_t seed, VectorXi* face = nullptr);

// Exact unsigned distance from each point of P to the surface (V, T) (union of its closed triangles).
Eigen::VectorXd point_mesh_distance(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                                    const Eigen::Ref<const MatrixX3iR>& T, VectorXi* face = nullptr);

struct OneSidedDistance {
  double max = 0, mean = 0, rms = 0, min = 0;
  Eigen::Index n_samples = 0;
};

// Distances from samples of A to surface B, as Metro / MeshLab's Hausdorff filter with SampleVert and
// SampleFace: every vertex of A referenced by TA (if include_vertices) plus n_samples area-uniform
// points of A (sample_surface with seed).
OneSidedDistance one_sided_distance(const Eigen::Ref<const MatrixX3dR>& VA, const Eigen::Ref<const MatrixX3iR>& TA,
                                    const Eigen::Ref<const MatrixX3dR>& VB, const Eigen::Ref<const MatrixX3iR>& TB,
                                    Eigen::Index n_samples, bool include_vertices, std::uint64_t seed);

}  // namespace meshmark
