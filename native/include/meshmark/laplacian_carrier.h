// meshmark: the per-vertex scalar that carries the Laplacian watermark (thesis ch. 7).
//
// The thesis bins d_i = ||L_i|| (eq. 7.1.5) of the uniform Laplacian L = K X (eqs. 7.1.2-7.1.3).
// meshmark divides it by the global mean edge length (docs/laplacian.md, "Beyond the thesis" (c)).
// Under skinning every vertex's value then drifts with the global scale, and the tangential part of
// L_i changes whenever the 1-ring is stretched. The alternatives below are measured on Blender rigs in
// docs/carrier.md (examples/carrier_skinning.py). All are invariant under translation, rotation,
// uniform scaling and vertex reordering, as the thesis requires of its carrier (§7.4.2).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/vertex_adjacency.h"

namespace meshmark {

enum class LaplacianCarrier : int {
  Thesis = 0,     // s_i = ||L_i|| / scale              (eq. 7.1.5; scale = mean edge length, or 1)
  Local = 1,      // s_i = ||L_i|| / l_i                 (l_i = mean length of the edges at v_i)
  Normal = 2,     // s_i = (L_i . n_i) / l_i             (signed normal component; n_i area-weighted normal)
  CotLocal = 3,   // s_i = ||C_i|| l_i / A_i             (C_i = 1/2 sum_j (cot a_ij + cot b_ij)(x_i - x_j),
                  //                                      A_i = one third of the incident triangle areas)
  CotNormal = 4,  // s_i = (C_i . n_i) l_i / A_i         (signed mean-curvature normal, in units of l_i)
  NormalGlobal = 5,  // s_i = (L_i . n_i) / scale        (signed normal component in the thesis carrier's unit)
};

struct LaplacianCarrierField {
  Eigen::VectorXd value;  // (n,) s_i; 0 for vertices without edges (or without area, cotangent kinds)
  // For the embedding (only when asked): the change of the uniform Laplacian L_i that raises s_i by
  // one unit, to first order, is direction_i * gain_i (eq. 7.2.19 generalised: for Thesis this is
  // L_i / ||L_i|| * scale, so that dL = L (d^/d - 1) as in the thesis).
  MatrixX3dR direction;   // (n, 3) unit vectors
  Eigen::VectorXd gain;   // (n,)
};

// The carrier scalar of every vertex, from the unique edges E (the polygon edge graph: L_i is the
// thesis' uniform Laplacian over it, eqs. 7.1.2-7.1.3 with eps = 0) and the triangles T (normals and
// cotangent weights; T may be empty for Thesis and Local). One pass over the edges, one over the
// triangles; no adjacency is built.
// compress > 0 bins asinh(s_i / compress) instead of s_i: linear near 0, logarithmic for |s| >> compress,
// so that K uniform bins (eq. 7.1.6) grow with |s| (long-tailed histograms give fewer tiny pairs).
LaplacianCarrierField laplacian_carrier(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX2iR>& E,
                                        const Eigen::Ref<const MatrixX3iR>& T, LaplacianCarrier kind,
                                        double scale = 1.0, bool with_direction = false, double compress = 0.0);

// The same from the CSR adjacency (the embedding's rounds: each vertex gathers its 1-ring, no scattered
// writes). Identical values up to the summation order.
LaplacianCarrierField laplacian_carrier(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A,
                                        const Eigen::Ref<const MatrixX3iR>& T, LaplacianCarrier kind,
                                        double scale = 1.0, bool with_direction = false, double compress = 0.0);

// The embedding's rounds for the Local carrier without compression (laplacian_watermark.cpp): s_i of
// every vertex, bit-identical to the adjacency overload's value, without the direction and gain of
// every vertex (only the moved ones need them: laplacian_local_change). One gather pass, each edge
// length computed at its lower end and added to both. branch_free: every neighbour's length is
// computed and the ones with j < i masked to +0, instead of a branch on j > i. The branch mispredicts
// on most neighbours of a breadth-first-numbered mesh; the masking doubles the square roots and the
// scattered additions, which costs more once the mesh no longer fits in the cache (measured, bunny
// 35k vertices: 0.64 vs 0.85 ms per call; 1.28M vertices: 32 vs 21 ms).
struct LocalRingCarrier {
  Eigen::VectorXd value;  // (n,) s_i = ||L_i|| / l_i (eq. 7.1.5 over l_i); 0 without edges
  Eigen::VectorXd ell;    // (n,) l_i, summed exactly as the adjacency overload sums it
  Eigen::VectorXd elen;   // scratch
};
// Fills `out`, reusing its storage (the embedding calls this every round: no fresh pages to fault in).
void laplacian_local_ring(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, LocalRingCarrier& out,
                          bool branch_free = false);

// dL_i = direction_i gain_i (d^_i - s_i) (eq. 7.2.19 generalised, laplacian_carrier.h above) for the
// vertices whose target d_target differs from s_i, 0 elsewhere: L_i is gathered again for those alone.
// Bit-identical to the same product formed from laplacian_carrier(V, A, ..., Local, 1, true).
// dL is resized to (n, 3) and overwritten (its storage reused).
void laplacian_local_change(const Eigen::Ref<const MatrixX3dR>& V, const Adjacency& A, const LocalRingCarrier& R,
                            const Eigen::VectorXd& d_target, MatrixX3dR& dL);

}  // namespace meshmark
