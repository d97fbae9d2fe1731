// meshmark: weighted disagreement of every codeword of a packed codebook with a received word, the
// maximum-likelihood search of the keyed random code (src/meshmark/watermark/keyed_code.py,
// docs/coding.md §1).
//
// book: n_words rows of n_bytes bytes, each a codeword packed MSB first (bit i of a codeword is bit
// 7 - i % 8 of byte i / 8); received: n_bytes bytes, the hard decisions packed the same way; weights:
// one non-negative integer per code bit (8 * n_bytes entries, 0 beyond the code length). Returns
// D[w] = sum_i weights[i] * [bit i of codeword w != bit i of received].
#pragma once
#include <cstdint>
#include <vector>

namespace meshmark {

std::vector<std::int32_t> codebook_disagreement(const std::uint8_t* book, std::int64_t n_words, int n_bytes,
                                                const std::uint8_t* received, const std::vector<std::int32_t>& weights);

}  // namespace meshmark
