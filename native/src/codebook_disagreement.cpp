#include "meshmark/codebook_disagreement.h"

#include <stdexcept>

namespace meshmark {

std::vector<std::int32_t> codebook_disagreement(const std::uint8_t* book, std::int64_t n_words, int n_bytes,
                                                const std::uint8_t* received, const std::vector<std::int32_t>& weights) {
  if (n_bytes <= 0 || n_words < 0 || weights.size() != static_cast<std::size_t>(n_bytes) * 8)
    throw std::invalid_argument("codebook_disagreement: weights must have 8 * n_bytes entries");
  // table[j][b]: the weight of the disagreeing bits when byte j of a codeword XOR the received byte is b
  std::vector<std::int32_t> table(static_cast<std::size_t>(n_bytes) * 256, 0);
  for (int j = 0; j < n_bytes; ++j)
    for (int b = 1; b < 256; ++b) {
      std::int32_t s = 0;
      for (int l = 0; l < 8; ++l)
        if (b & (0x80 >> l)) s += weights[static_cast<std::size_t>(j) * 8 + l];
      table[static_cast<std::size_t>(j) * 256 + b] = s;
    }
  std::vector<std::int32_t> D(static_cast<std::size_t>(n_words));
  for (std::int64_t w = 0; w < n_words; ++w) {
    const std::uint8_t* c = book + w * n_bytes;
    std::int32_t s = 0;
    for (int j = 0; j < n_bytes; ++j) s += table[static_cast<std::size_t>(j) * 256 + (c[j] ^ received[j])];
    D[static_cast<std::size_t>(w)] = s;
  }
  return D;
}

}  // namespace meshmark
