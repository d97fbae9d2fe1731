// meshmark: similarity registration of a point set to a surface (informed tracing's alignment).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/triangle_tree.h"

#include <cmath>
#include <vector>

namespace meshmark {

// x -> s R x + t
struct Similarity {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  double s = 1.0;
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
};

struct IcpResult {
  Similarity T;
  double rms = 0;             // RMS point-to-surface distance of the kept points, after the last step
  double kept_fraction = 0;   // fraction of P kept by the trimming in the last step
  int iterations = 0;
  int start = -1;             // index of the winning start (align_similarity)
};

// Umeyama's least-squares similarity (IEEE PAMI 13(4), 1991, eqs. 40-42) mapping the rows of P onto
// the rows of Q; with_scale = false fixes s = fixed_scale (R and t are fitted for it).
Similarity umeyama(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& Q, bool with_scale,
                   double fixed_scale = 1.0);

// Trimmed ICP with scale (Chetverikov et al.'s trimmed ICP, Umeyama's step): from each start, every
// iteration maps P by the current similarity, finds the nearest point of (V, T) (exact, TriangleTree),
// keeps the points whose distance is at most min(quantile(trim), 4 quantile(0.25)) and refits. Each
// start runs `coarse` point-to-point iterations; the `top` ones with the smallest kept RMS run `refine`
// more; the best of those goes on for `fine`
// linearised point-to-plane iterations with scale (plane of the nearest triangle), or until the RMS
// changes by less than 1e-9 relatively. After each step s is clamped to [scale_min, scale_max]. MeshError for an empty start list, P or T.
IcpResult align_similarity(const Eigen::Ref<const MatrixX3dR>& P, const Eigen::Ref<const MatrixX3dR>& V,
                           const Eigen::Ref<const MatrixX3iR>& T, const std::vector<Similarity>& starts,
                           int coarse, int fine, double trim, bool with_scale, double scale_min = 0,
                           double scale_max = HUGE_VAL, int top = 1, int refine = 0);

// The same on a tree built once (the original's, reused by every call of a trace). The starts, and
// then the `top` refined ones, run on the machine's threads (one start per thread at a time); the
// result does not depend on the number of threads.
IcpResult align_similarity(const Eigen::Ref<const MatrixX3dR>& P, const TriangleTree& tree,
                           const std::vector<Similarity>& starts, int coarse, int fine, double trim, bool with_scale,
                           double scale_min = 0, double scale_max = HUGE_VAL, int top = 1, int refine = 0);

}  // namespace meshmark
