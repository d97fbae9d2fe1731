// meshmark: optimal and curvature-adaptive dithered-quantization levels (thesis §4.1.2-§4.3.1).
#pragma once
#include "meshmark/mesh.h"

#include <optional>

namespace meshmark {

// Per-triangle estimate of the expected normal change when noise is added to all three vertices:
enum class NoiseBound {
  Min,   // E_min  = E(theta_1), the smallest height h_1                                   (eq. 4.1.10)
  Appr,  // E_appr = eta (E(theta_1) + E(theta_2) + E(theta_3))                            (eq. 4.1.16)
  Max,   // E_max  = 2 E_min                                                                (eq. 4.1.15)
};

struct TriangleHeights {
  // (t,3) inverse heights 1/h1 >= 1/h2 >= 1/h3 (1 / model units); 0 for unusable triangles. Stored
  // inverted because everything uses l/h (and sum 1/h_k = 1/rho, eq. 4.1.17).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> inv_h;
  VectorXb usable;    // (t,) 1 if the triangle has a finite, non-zero area (others are skipped everywhere)
  Eigen::Index n_usable = 0;
};

// Heights h_k = 2 area / |opposite edge| of every triangle (as inverse heights |edge| / 2 area).
TriangleHeights triangle_heights(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

// E_mesh(theta) = sum_j E_j / M over the usable triangles                                   (eq. 4.2.18)
// for noise of half-width l (model units, as the heights) with E_j the chosen bound; exact = true uses
// E(theta) of eq. 4.1.7/4.1.8, exact = false its tangent r/2 (eq. 4.1.9, so that E_appr = eta l / 2 rho,
// eq. 4.1.17). NaN without usable triangles.
double mesh_normal_expectation(const TriangleHeights& H, double l, NoiseBound bound, bool exact, double eta);

enum class LevelFormula {
  Auto,    // the closed form, unless it misestimates E_mesh at its level by more than switch_tol (then Exact)
  Linear,  // the closed forms eqs. 4.3.20-4.3.21 (and their E_max analogue)
  Exact,   // the smallest integer k with E_mesh(k) <= eps, E(theta) of eq. 4.1.7 (the MPII case, Fig. 4.4)
};

struct QuantizationLevel {
  int level = 0;            // the level i (eq. 4.3.19), clamped to 0..32
  int level_unclamped = 0;  // the same without the clamp (searched within -64..160)
  int level_linear = 0;     // the closed form (unclamped)
  bool used_exact = false;  // whether the exact search decided the level
  double e_linear = 0;      // linear E_mesh at level_linear, radians
  double e_exact = 0;       // exact E_mesh at level_linear, radians
  double e_level = 0;       // E_mesh at the returned (unclamped) level with the formula used
  double cube = 0;          // L, the largest extent of the vertices (the bounding cube of the fixed point)
  Eigen::Index n_triangles = 0;  // usable triangles M
};

// Level i = argmin_k { k | E_mesh(theta) <= eps } for the dithered 32-bit fixed point in the bounding
// cube (attacks' dither_bits Fixed32: lo = per-axis min, side L = largest extent over all rows of V):
// keeping k bits replaces a cell of side L 2^-k, i.e. noise with cubic support 2l = 2^-k L (§4.3.1).
// The thesis writes arg max but means the coarsest level that meets the tolerance (E_mesh decreases
// with k). Closed forms (heights in units of L):
//   Min:  i = ceil(-2 - log2(M eps / sum_j 1/h'_j))                                      (eq. 4.3.20)
//   Appr: i = ceil(-2 - log2(M eps / (eta sum_j 1/rho_j)))                               (eq. 4.3.21)
//   Max:  i = ceil(-2 - log2(M eps / (2 sum_j 1/h'_j)))
// eps in radians. MeshError if eps <= 0 or not finite, eta <= 0, switch_tol < 0, or no usable triangle.
QuantizationLevel quantization_level(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                     double eps, NoiseBound bound, LevelFormula formula, double eta,
                                     double switch_tol = 0.1);

struct AdaptiveLevels {
  VectorXi vertex_level;    // (n,) clamped to 0..32: max over the incident usable triangles (§4.3.1);
                            // 0 for unreferenced vertices, 32 for vertices with only unusable triangles
  VectorXi triangle_level;  // (t,) unclamped level of each triangle (INT32_MIN for unusable ones)
  Eigen::VectorXd triangle_tolerance;  // (t,) eps_j, radians (NaN for unusable ones)
};

// Curvature-adaptive levels (eqs. 4.3.23-4.3.25): with kappa_n the vertex curvature (gaussian_curvature),
//   eps_j = min over the 3 vertices n of { alpha - phi(kappa_n; alpha, mu, sigma) + eps0 },
//   phi(x) = alpha exp(-(x - mu)^2 / (2 sigma^2))                                          (eq. 4.3.24)
//   i_j   = argmin_k { k | E_appr,j(theta) <= eps_j }                                       (eq. 4.3.25)
// with E_appr,j evaluated with the exact E(theta) (for one triangle the search is as cheap as the
// closed form). Thesis constants: alpha = 0.7979, mu = 0, sigma = 0.5, eps0 = 0.0017, eta = 0.608.
// MeshError if eps0 <= 0, sigma <= 0, eta <= 0, kappa has the wrong size, or no usable triangle.
AdaptiveLevels adaptive_levels(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                               const Eigen::Ref<const Eigen::VectorXd>& kappa, double eps0, double alpha, double mu,
                               double sigma, double eta);

// Level-only fast paths (meshmark.stego computes levels three times per embed + extract). Each gives
// exactly the result of the general function, in one pass over the triangles and without the (t,3)
// heights, or nullopt where that equality cannot be guaranteed (the caller then runs the general one).
//
// quantization_level(V, T, eps, bound, formula, eta, switch_tol).level, with the triangles visited in
// vertex-block order (the gathers stay in cache). Its sums then differ from quantization_level's by
// rounding only (< 3 M u relative for M usable triangles, all terms being >= 0); every comparison that
// decides the level (E_lin or E_mesh against eps, the Auto switch) is made with that margin, and
// nullopt is returned when one is closer than it.
std::optional<int> quantization_level_only(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T,
                                           double eps, NoiseBound bound, LevelFormula formula, double eta,
                                           double switch_tol = 0.1);

// adaptive_levels(V, T, kappa, eps0, alpha = 0, mu, sigma, eta).vertex_level for any kappa that has no
// NaN: with alpha = 0, eps_j = 0 - 0 exp(.) + eps0 = eps0 exactly, so no curvature is needed. kappa
// (gaussian_curvature: 2 pi or pi minus a sum of atan2 angles) is finite whenever the coordinates are
// finite and below 2^400 in magnitude (no dot product overflows); nullopt for other coordinates.
std::optional<VectorXi> uniform_adaptive_levels(const Eigen::Ref<const MatrixX3dR>& V,
                                                const Eigen::Ref<const MatrixX3iR>& T, double eps0, double eta);

}  // namespace meshmark
