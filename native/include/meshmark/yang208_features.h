// meshmark: the YANG208 steganalysis feature vector of thesis §8.1 (docs/steganalysis.md §2).
//
// 1. Normalise: PCA frame, unit cube centred at (0.5, 0.5, 0.5) (§8.1.1, feature_frame.h: where two
//    principal variances agree to 1e-3 the axes are not determined; their components are pooled).
// 2. Calibrate: the reference mesh M' is one step of Laplacian smoothing with the Kirchhoff matrix R
//    of eq. 8.1.2, normalised by the valence: x' = x - D^-1 R x (each vertex moves to the mean of its
//    neighbours, the umbrella step with lambda = 1), so that M - M' is the valence-normalised
//    Laplacian coordinate (§8.1.3: "essentially ... the Laplacian coordinates of M").
// 3. 26 vectors (§8.1.3), in this order:
//    for valence class  < 6, = 6, > 6 (interior vertices only: a vertex on an edge with a face count
//    other than 2 is left out), for Cartesian then Laplacian (delta = R x) coordinates:
//    |dx|, |dy|, |dz| and the length (Cartesian: ||x - x'||; Laplacian: | ||delta|| - ||delta'|| |,
//    Fig. 8.1); then |theta - theta'| over the interior edges (dihedral angles, dihedral_angles.h)
//    and the angle between the face normals of M and M' (faces non-degenerate in both).
// 4. 8 statistics each (§8.1.4, feature_statistics.h): log_moments with floor 1e-7 (kFeatureLogFloor), then
//    histogram_moments (Freedman-Diaconis bins). Feature 8j + s is statistic s of vector j.
//
// Faces must be triangles (callers triangulate polygons). Only vertices used by a face take part.
// MeshError for fewer than 4 referenced vertices or no triangle ("too small for the features").
#pragma once
#include "meshmark/feature_statistics.h"
#include "meshmark/mesh.h"

namespace meshmark {

constexpr int kYang208Size = 208;
// An element whose storage-noise floor exceeds 0.1 (unit-cube lengths, radians) is left out.
constexpr double kYang208Cap = 0.1;

Eigen::VectorXd yang208_features(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
