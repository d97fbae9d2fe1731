// meshmark: LFS76s, the stabilised variant of the LFS76 features of Li and Bors (Information Sciences
// 415-416, 2017) that the protocol and the default model use (docs/steganalysis.md §3; the published
// computation is lfs76_features.h).
//
// Reference mesh: heat diffusion with the combinatorial Laplacian I - D^-1 W in explicit steps,
// x <- x - dt (I - D^-1 W) x, t_max / dt steps (dt = 0.3, t_max = 3: 10 steps, as in the published runs).
// Normalisation: feature_frame.h from the original mesh, applied to both meshes (published: each mesh on
// its own with trans * V, the transpose of the PCA projection). 19 vectors, in the published order:
//   1-12 |dx|, |dy|, |dz| (pooled where the principal axes are not determined); 13-16 | ||x - c|| -
//   ||x' - c|| |, c = the vertex centroid; 17-28 Laplacian (Kirchhoff, eq. 8.1.2) components; 29-32
//   | ||delta|| - ||delta'|| |; 33-36 face-normal angles; 37-40 |dihedral - dihedral'|; 41-44 vertex-normal
//   angles (area-weighted normals); 45-48 |K - K'| (Gaussian curvature); 49-52 |r - r'| (curvature
//   ratio min|k| / max|k|); 53-64 |d az|, |d elev|, |d rho| (spherical coordinates about each mesh's
//   centroid, degrees, azimuth differences wrapped to [0, 180], about a determined axis; with all three
//   axes undetermined the angle between x - c and x' - c fills both angle slots); 65-76 the same on the
//   edges' differences. Curvatures (not the authors' GetCurvatures): Meyer et al.'s operators with
//   barycentric areas, K = (2 pi - angle sum) / A, H = |cotangent Laplacian| / (4 A), k = H +- sqrt(max(H^2
//   - K, 0)), on interior vertices. Statistics (feature_statistics.h): each value floored at 10x its
//   float32 storage noise, elements whose floor exceeds 0.1 (unit cube, radians, ratio; 5.7 degrees)
//   left out, regularised log-moments. Faces must be triangles; vertices not used by a face take no part.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kLfs76sSize = 76;

Eigen::VectorXd lfs76s_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                double dt = 0.3, double t_max = 3.0);

}  // namespace meshmark
