// meshmark: exp and ln over arrays, written so that the compiler vectorises them (SSE2; AVX2 clones
// chosen at run time on x86-64 Linux with GCC): the histogram mappings x' = x^k = exp(k ln x) of Cho
// et al.'s watermarks (thesis §2.2.2) evaluate millions of them. Within 1 ulp of std::exp and 2 ulp
// of std::log on [0, 1]; the same bits on every x86-64 CPU (no FMA contraction).
#pragma once
#include <cstddef>

namespace meshmark {

// out[j] = exp(k * l[j]) for j < n (out may alias l); 0 where k * l[j] <= -708 (with k > 0 this
// includes l[j] = -inf, i.e. 0^k = 0).
void exp_scaled(const double* l, double k, double* out, std::size_t n);

// x[j] = ln x[j] in place, for x[j] >= 0 finite: -inf at 0, subnormals handled.
void log_inplace(double* x, std::size_t n);

// The same, returning sum_j x_j^p ln x_j (p = 1 or 2) over x_j > 0, summed in an unspecified order
// (a derivative for a search's first step, not a result).
double log_inplace_moment(double* x, std::size_t n, int p);

}  // namespace meshmark
