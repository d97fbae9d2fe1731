// C++ unit tests of the §4.3.2 steganography core and the Chao et al. 2009 baseline.
#include "meshmark/chao_stego.h"
#include "meshmark/rng.h"
#include "meshmark/stego_lsb.h"
#include "meshmark/stego_order.h"

#include <gtest/gtest.h>
#include <cmath>
#include <numeric>

using namespace meshmark;

namespace {
MatrixX3dR cloud(Rng& r, Eigen::Index n, double scale, double shift) {
  MatrixX3dR V(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) V(i, a) = shift + scale * r.normal() * (a + 1);
  return V;
}
std::vector<std::uint8_t> random_bytes(Rng& r, std::int64_t nbits) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(nbits / 8 + 1));
  for (auto& x : b) x = static_cast<std::uint8_t>(r.bits());
  return b;
}
}  // namespace

TEST(Stego, Fixed32FrameIsRebuiltFromTheMarkedMesh) {
  Rng r(7);
  for (int trial = 0; trial < 100; ++trial) {
    const MatrixX3dR V = cloud(r, 40, std::pow(10.0, r.uniform(-3, 3)), std::pow(10.0, r.uniform(-3, 3)) * r.normal());
    const StegoFrame fr = stego_frame(V, StegoPrecision::Fixed32);
    const MatrixX3dR C = stego_snap(V, StegoPrecision::Fixed32, fr);
    VectorXi t = VectorXi::Constant(40, fr.E - 2);  // coarsest cells allowed
    VectorXi order(40);
    std::iota(order.data(), order.data() + 40, 0);
    const VectorXb first = VectorXb::Ones(40);
    const std::int64_t cap = stego_capacity(C, t, StegoPrecision::Fixed32, fr, order, first);
    EXPECT_EQ(cap, 40 * 3 * 29);  // k = t - s = 30 low bits: bits 1..29 carry, bit 0 is the LSB
    const MatrixX3dR M = stego_write_bits(C, t, StegoPrecision::Fixed32, fr, order, first, random_bytes(r, cap), cap);
    const StegoFrame f2 = stego_frame(M, StegoPrecision::Fixed32);
    EXPECT_EQ(f2.E, fr.E);
    EXPECT_EQ(f2.o, fr.o);
    EXPECT_EQ(stego_quantize(M, t, StegoPrecision::Fixed32, fr), stego_quantize(C, t, StegoPrecision::Fixed32, fr));
  }
}

TEST(Stego, BitsRoundTripInEveryPrecision) {
  Rng r(3);
  const MatrixX3dR V = cloud(r, 200, 0.05, 0.3);
  for (StegoPrecision p : {StegoPrecision::Fixed32, StegoPrecision::Float32, StegoPrecision::Float64}) {
    const StegoFrame fr = stego_frame(V, p);
    const MatrixX3dR C = stego_snap(V, p, fr);
    VectorXi t = VectorXi::Constant(200, static_cast<Index>(std::floor(std::log2(0.05))) - 12);
    VectorXi order(200);
    std::iota(order.data(), order.data() + 200, 0);
    const VectorXb first = VectorXb::Ones(200);
    const std::int64_t cap = stego_capacity(C, t, p, fr, order, first);
    ASSERT_GT(cap, 0);
    auto bits = random_bytes(r, cap);
    const MatrixX3dR M = stego_write_bits(C, t, p, fr, order, first, bits, cap);
    auto back = stego_read_bits(M, t, p, fr, order, first, cap);
    bits.resize(back.size());
    if (cap % 8) bits.back() &= static_cast<std::uint8_t>(0xff << (8 - cap % 8));
    EXPECT_EQ(back, bits);
    // only bits below the cell change: |M - C| < 2^t
    EXPECT_LT((M - C).cwiseAbs().maxCoeff(), std::ldexp(1.0, t[0]));
    // the LSB stream is independent of the message bits
    const std::int64_t slots = stego_lsb_capacity(M, p, fr, first, order);
    EXPECT_EQ(slots, 600);
    auto lsb = random_bytes(r, slots);
    const MatrixX3dR M2 = stego_write_lsb(M, p, fr, order, first, lsb, slots);
    EXPECT_EQ(stego_read_bits(M2, t, p, fr, order, first, cap), back);
    auto lb = stego_read_lsb(M2, p, fr, order, first, slots);
    lsb.resize(lb.size());
    EXPECT_EQ(lb, lsb);
    EXPECT_EQ(stego_clear_lsb(M2, p, fr), stego_clear_lsb(M, p, fr));
  }
}

TEST(Stego, OrderIsBitwisePermutationInvariant) {
  Rng r(11);
  const Eigen::Index n = 500;
  const MatrixX3dR V = cloud(r, n, 1.0, 2.0);
  const StegoFrame fr = stego_frame(V, StegoPrecision::Fixed32);
  const MatrixX3dR Q = stego_quantize(stego_snap(V, StegoPrecision::Fixed32, fr),
                                      VectorXi::Constant(n, fr.E - 10), StegoPrecision::Fixed32, fr);
  VectorXi t = VectorXi::Constant(n, fr.E - 10);
  Polygons P;  // no faces
  P.offsets = VectorXo::Zero(1);
  const StegoOrder a = stego_order(Q, t, fr.E, fr.o, P);
  std::vector<Index> perm(static_cast<std::size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  for (Eigen::Index i = n - 1; i > 0; --i) std::swap(perm[static_cast<std::size_t>(i)], perm[r.below(i + 1)]);
  MatrixX3dR Qp(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) Qp.row(i) = Q.row(perm[static_cast<std::size_t>(i)]);
  const StegoOrder b = stego_order(Qp, t, fr.E, fr.o, P);
  EXPECT_EQ(a.axis, b.axis);  // bitwise
  EXPECT_EQ(a.centroid, b.centroid);
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_EQ(perm[static_cast<std::size_t>(b.order[k])], a.order[k]);
}

TEST(Chao, ExactWithTheFrameAndThirtyBitsPerVertex) {
  Rng r(5);
  const MatrixX3dR V = cloud(r, 1000, 1.0, 0.0);
  const ChaoFrame f = chao_frame(V);
  const Eigen::Index cap = chao_carriers(V.rows(), f).size() * 30;
  EXPECT_GE(cap, (1000 - 6) * 30);
  VectorXb bits(cap);
  for (Eigen::Index i = 0; i < cap; ++i) bits[i] = static_cast<std::uint8_t>(r.bits() & 1);
  const MatrixX3dR M = chao_embed(V, f, bits, 10, 10000);
  EXPECT_EQ(chao_extract(M, f, cap, 10, 10000), bits);
  for (int a = 0; a < 3; ++a) {  // extreme vertices unchanged
    EXPECT_EQ(M.row(f.ia[a]), V.row(f.ia[a]));
    EXPECT_EQ(M.row(f.ib[a]), V.row(f.ib[a]));
  }
}
