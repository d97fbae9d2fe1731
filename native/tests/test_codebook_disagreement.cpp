// C++ unit test of codebook_disagreement (codebook_disagreement.h): the byte-table search equals a
// plain bit-by-bit count on random codebooks, weights and received words, and a codeword equal to the
// received word has disagreement 0.
#include "meshmark/codebook_disagreement.h"

#include <gtest/gtest.h>
#include <random>
#include <vector>

using namespace meshmark;

TEST(CodebookDisagreement, EqualsPlainBitCount) {
  std::mt19937 rng(7);
  for (int n_bytes : {1, 5, 14, 32}) {
    const int W = 300;
    std::vector<std::uint8_t> book(static_cast<std::size_t>(W) * n_bytes), r(n_bytes);
    std::vector<std::int32_t> wt(static_cast<std::size_t>(n_bytes) * 8);
    for (auto& b : book) b = static_cast<std::uint8_t>(rng() & 0xFF);
    for (auto& b : r) b = static_cast<std::uint8_t>(rng() & 0xFF);
    for (auto& w : wt) w = static_cast<std::int32_t>(rng() % 9);
    for (int j = 0; j < n_bytes; ++j) book[static_cast<std::size_t>(17) * n_bytes + j] = r[j];  // word 17 = received
    const auto D = codebook_disagreement(book.data(), W, n_bytes, r.data(), wt);
    ASSERT_EQ(D.size(), static_cast<std::size_t>(W));
    EXPECT_EQ(D[17], 0);
    for (int w = 0; w < W; ++w) {
      std::int32_t s = 0;
      for (int i = 0; i < 8 * n_bytes; ++i) {
        const int cb = (book[static_cast<std::size_t>(w) * n_bytes + i / 8] >> (7 - i % 8)) & 1;
        const int rb = (r[i / 8] >> (7 - i % 8)) & 1;
        s += cb != rb ? wt[i] : 0;
      }
      EXPECT_EQ(D[w], s) << "word " << w << " n_bytes " << n_bytes;
    }
  }
}

TEST(CodebookDisagreement, RejectsWrongWeightCount) {
  std::vector<std::uint8_t> book(4), r(2);
  EXPECT_THROW(codebook_disagreement(book.data(), 2, 2, r.data(), std::vector<std::int32_t>(15)), std::invalid_argument);
}
