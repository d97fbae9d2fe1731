// meshmark: keyed i.i.d. standard normal fields (the w_j of informed tracing's patterns).
#pragma once
#include "meshmark/mesh.h"

#include <cstdint>
#include <vector>

namespace meshmark {

// Entry i of the field with 64-bit seed s: Box-Muller, z = sqrt(-2 ln u1) cos(2 pi u2), with
// u_k = ((h_k >> 11) + 0.5) 2^-53 and h_1, h_2 the SplitMix64 finaliser of s + (2i + 1) g and
// s + (2i + 2) g (g = 0x9E3779B97F4A7C15). Counter-based: any entry is computed on its own, the same
// on every machine.
double keyed_gaussian(std::uint64_t seed, std::int64_t i);

// (n, N) matrix: column j is the field of seeds[j] at entries 0 .. n-1.
Eigen::MatrixXd keyed_gaussians(const std::vector<std::uint64_t>& seeds, Eigen::Index n);

// (N,) dot products <u, w_j> of u (n,) with the field of each seed, without storing the fields.
Eigen::VectorXd keyed_gaussian_dots(const Eigen::Ref<const Eigen::VectorXd>& u, const std::vector<std::uint64_t>& seeds);

}  // namespace meshmark
