// meshmark: the LFS76 steganalysis features of Li and Bors (Information Sciences 415-416, 2017), the sound
// version (docs/steganalysis.md §3).
//
// Reference mesh: heat diffusion with the combinatorial Laplacian I - D^-1 W in explicit steps,
// x <- x - dt (I - D^-1 W) x, Tmax / dt steps (dt = 0.3, Tmax = 3: 10 steps, as in the published runs).
// Normalisation: the similarity of unit_cube_normalize.h taken from the original mesh and applied to
// both meshes (the published preprocess.m normalises each mesh on its own with trans*V, the transpose
// of the PCA projection: not rotation-invariant); norms and spherical coordinates about fixed centres
// (bounding-box centre, centroid), never the min corner. 19 vectors x 4 log-moments (log(|d| + 1e-7),
// not the published 2^-52, which is below the rounding noise of the differences; mean, variance (N - 1), skewness, kurtosis (biased, non-excess)):
//   1-12 |dx|, |dy|, |dz|; 13-16 | ||x - c|| - ||x' - c|| |, c = (0.5, 0.5, 0.5); 17-28 Laplacian
//   (Kirchhoff, eq. 8.1.2) components; 29-32 | ||delta|| - ||delta'|| |; 33-36 face-normal angles;
//   37-40 |dihedral - dihedral'|; 41-44 vertex-normal angles; 45-48 |K - K'| (Gaussian curvature);
//   49-52 |r - r'| (curvature ratio min|k|/max|k|); 53-64 |d az|, |d elev|, |d rho| (spherical
//   coordinates about each mesh's centroid, degrees, azimuth differences wrapped to [0, 180]);
//   65-76 the same on the edge differences | |az_a - az_b| - |az'_a - az'_b| | etc.
// Curvatures (not the authors' GetCurvatures): Meyer et al.'s discrete operators with barycentric
// areas, K = (2 pi - angle sum) / A, H = |cotangent Laplacian| / (4 A), k = H +- sqrt(max(H^2 - K, 0)),
// on interior vertices only (the published code indexes a missing face on open meshes). Faces must be
// triangles; vertices not used by a face take no part.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kLfs76Size = 76;

Eigen::VectorXd lfs76_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               double dt = 0.3, double t_max = 3.0);

}  // namespace meshmark
