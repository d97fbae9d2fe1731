// C++ unit tests of the convolutional code (convolutional_code.h): the encoder's impulse response is
// the generators (octal notation, current input in the most significant bit), tail-biting encoding
// is cyclic, and the Viterbi decoder inverts the encoder noise-free and corrects a single flip.
#include "meshmark/convolutional_code.h"
#include "meshmark/error.h"

#include <gtest/gtest.h>
#include <random>
#include <vector>

using namespace meshmark;

namespace {
const std::vector<int> G = {0133, 0171, 0165};  // LTE, 3GPP TS 36.212 §5.1.3.1
constexpr int K = 7;

std::vector<double> llr_of(const std::vector<std::uint8_t>& c) {
  std::vector<double> y(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) y[i] = c[i] ? 1.0 : -1.0;
  return y;
}
}  // namespace

TEST(ConvolutionalCode, ImpulseResponseIsTheGenerators) {
  std::vector<std::uint8_t> u(1, 1);
  const auto c = conv_encode(u, G, K, false);  // 1 followed by 6 zero tail bits
  ASSERT_EQ(c.size(), 3u * 7u);
  for (int j = 0; j < 3; ++j)
    for (int t = 0; t < 7; ++t) EXPECT_EQ(c[3 * t + j], (G[j] >> (K - 1 - t)) & 1) << "generator " << j << " tap " << t;
}

TEST(ConvolutionalCode, TailBitingIsCyclic) {
  std::mt19937 rng(1);
  std::vector<std::uint8_t> u(30);
  for (auto& b : u) b = rng() & 1;
  const auto c = conv_encode(u, G, K, true);
  std::vector<std::uint8_t> r(u.begin() + 5, u.end());  // rotate the input by 5 steps
  r.insert(r.end(), u.begin(), u.begin() + 5);
  const auto cr = conv_encode(r, G, K, true);
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(cr[i], c[(i + 15) % c.size()]);
}

TEST(ConvolutionalCode, ViterbiInvertsAndCorrects) {
  std::mt19937 rng(2);
  for (int L : {1, 6, 7, 21, 36, 100}) {
    std::vector<std::uint8_t> u(L);
    for (auto& b : u) b = rng() & 1;
    for (bool tb : {false, true}) {
      auto y = llr_of(conv_encode(u, G, K, tb));
      EXPECT_EQ(viterbi_decode(y, G, K, L, tb, 42), u) << "L " << L << " tail-biting " << tb;
      if (L >= 21) {
        y[7] = -y[7];  // one flipped code bit (free distance 15)
        EXPECT_EQ(viterbi_decode(y, G, K, L, tb, 42), u) << "L " << L << " tail-biting " << tb;
      }
    }
  }
}

TEST(ConvolutionalCode, BadInputIsAnError) {
  EXPECT_THROW(conv_encode({1}, {0777}, 7, true), MeshError);  // does not fit K bits
  EXPECT_THROW(viterbi_decode({1.0, 1.0}, G, K, 1, true, 42), MeshError);  // 2 soft values, 3 expected
}
