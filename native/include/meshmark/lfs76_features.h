// meshmark: the LFS76 steganalysis features of Li and Bors (Information Sciences 415-416, 2017) as the
// authors' MATLAB code computes them (zl991/LFS76 @ 9afbc78: LFS76_fea.m), with one correction: the PCA
// projection trans' * V where preprocess.m applies trans * V (docs/steganalysis.md §3).
//
// Reference mesh: perform_mesh_heat_diffusion with L = I - D^-1 W (toolbox_graph, combinatorial W of
// triangulation2adjacency), x <- x - dt L x, round(t_max / dt) steps (published runs: dt 0.3, t_max 3), on
// the file's coordinates. Each mesh then normalised on its own (pca_min_corner_normalize.h). Vectors over
// every vertex / face / edge of the file, each + 2^-52 (NaN -> 2^-52):
//   1-12 |x - x'| per axis, 13-16 | ||x|| - ||x'|| | (about the min corner), 17-28 |(D - W)(x - x')| per
//   axis, 29-32 | ||(D - W) x|| - ||(D - W) x'|| |, 33-36 angles between geom3d faceNormal vectors
//   (cross of the normalised edges v1 - v0, v2 - v0; atan2 form of vectorAngle3d), 37-40 |dihedral -
//   dihedral'| (meshDihedralAngles), 41-44 angles between Max-weighted vertex normals (CalcVertexNormals),
//   45-48 |K - K'| and 49-52 |r - r'| of the Gaussian curvature k1 k2 and the ratio min|k| / max|k|
//   (rusinkiewicz_curvatures.h), 53-64 |d az|, |d elev|, |d rho| of enu2aer about each mesh's vertex mean
//   (degrees, azimuth in [0, 360), not unwrapped), 65-76 the same on the edges' | az_a - az_b | etc.
// Statistics: mean, var (N - 1), skewness, kurtosis (biased, not excess) of the log; in 1-12 and 17-28
// grouped by statistic ([mean x y z, var x y z, ...]) as published. A statistic MATLAB returns as NaN (zero
// variance) is 0 here. The published code stops on an edge with fewer than two faces (meshDihedralAngles
// indexes face 0): such edges are left out of 37-40 here, the only extension. Faces must be triangles.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kLfs76Size = 76;

Eigen::VectorXd lfs76_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               double dt = 0.3, double t_max = 3.0);

}  // namespace meshmark
