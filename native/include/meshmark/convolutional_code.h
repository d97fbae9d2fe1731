// meshmark: binary convolutional code (rate 1/n, constraint length K <= 10), encoder and soft-input
// Viterbi decoder, zero-terminated or tail-biting (docs/coding.md).
//
// Generators are given in the usual octal notation (e.g. LTE's rate-1/3 K = 7 code, 3GPP TS 36.212
// §5.1.3.1: 0133, 0171, 0165): the most significant of the K bits taps the current input, the least
// significant the oldest one. Code bits are interleaved per step: c[t * n + j] is generator j's
// output at step t.
#pragma once
#include <cstdint>
#include <vector>

namespace meshmark {

// Encode the 0/1 bits `u`. tail_biting: the encoder starts in the state its last K - 1 inputs leave
// it in (no tail, n * |u| code bits); otherwise it starts in state 0 and K - 1 zero bits are appended
// (n * (|u| + K - 1) code bits).
std::vector<std::uint8_t> conv_encode(const std::vector<std::uint8_t>& u, const std::vector<int>& generators, int K,
                                      bool tail_biting);

// Maximum-likelihood (zero-terminated) or wrap-around (tail-biting) Viterbi decoding of soft values
// `llr` (one per code bit, > 0 means bit 1, magnitude = reliability, 0 = erased/punctured); returns
// the n_info decoded bits. The path metric is sum_i llr_i * (2 c_i - 1), maximised. Tail-biting
// (wrap-around Viterbi): whole circular turns (at least `wrap` steps) from uniform metrics, then one
// turn with decisions kept; if its best path is not tail-biting, the exact tail-biting paths from
// the 8 best final states are searched and the best of all is returned (near-ML; tests compare it
// with brute-force ML).
std::vector<std::uint8_t> viterbi_decode(const std::vector<double>& llr, const std::vector<int>& generators, int K,
                                         int n_info, bool tail_biting, int wrap);

}  // namespace meshmark
