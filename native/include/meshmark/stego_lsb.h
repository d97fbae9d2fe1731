// meshmark: the bit layout of the adaptive high-capacity LSB steganography of thesis §4.3.2.
//
// Every coordinate is seen as an integer word with a unit exponent u (the weight 2^u of its bit 0):
//  * Fixed32: x = o_a + n 2^s, n a 32-bit unsigned integer, s = E - 32, in the dyadic cube of the frame
//    (E, o): E is the smallest integer for which every axis a has an o_a in 2^(E-1) Z with all its
//    coordinates in [o_a, o_a + 2^E) (o_a = floor(min_a / 2^(E-1)) 2^(E-1)). Unlike the thesis' exact
//    bounding cube, this frame is the same for the marked mesh as long as every vertex keeps at least
//    its 2 most significant bits (docs/stego.md has the proof), so blind extraction can rebuild it;
//  * Float32 / Float64: the IEEE-754 bit pattern, u = the weight of the last mantissa bit; zeros and
//    subnormals carry nothing and are never changed.
// A vertex with cell exponent t (it keeps the bits of weight >= 2^t: the thesis' "i most significant
// bits", t = floor(log2 L) - i) has k = t - u low bits per coordinate; bit 0 is the c = 1 LSB that
// carries the corrective vector e, bits 1 .. min(k, W) - 1 carry message bits (W = 31, 23, 52 the
// word's modifiable width), most significant first, coordinates x, y, z.
#pragma once
#include "meshmark/mesh.h"

#include <cstdint>
#include <vector>

namespace meshmark {

enum class StegoPrecision { Fixed32, Float32, Float64 };

struct StegoFrame {
  int E = 0;
  Eigen::Vector3d o = Eigen::Vector3d::Zero();  // Fixed32 cube origin; zero for Float*
};

// The frame (see above; Float*: E = the largest frexp exponent of a non-zero coordinate, of the
// float32-rounded values for Float32, o = 0). MeshError for an empty or all-zero V, non-finite values
// or (Fixed32) a mesh more than 2^20 of its sizes away from the origin.
StegoFrame stego_frame(const Eigen::Ref<const MatrixX3dR>& V, StegoPrecision p);

// The largest bounding-box extent max_a (max V_a - min V_a) (L of t = floor(log2 L) - i).
double stego_extent(const Eigen::Ref<const MatrixX3dR>& V);

// V as the carrier words: Fixed32 o_a + floor((x - o_a) / 2^s) 2^s, Float32 the nearest float32, Float64 V.
MatrixX3dR stego_snap(const Eigen::Ref<const MatrixX3dR>& V, StegoPrecision p, const StegoFrame& fr);

// Clamp range of the cell exponent t for this precision and frame: Fixed32 [s + 1, E - 2] (so that
// the frame of the marked mesh is the same), Float* [E - 110, E] (|e| fits an int8).
std::pair<int, int> stego_t_range(StegoPrecision p, int E);

// The unmarked quantized vertices: bits 0 .. max(1, min(k, W)) - 1 of every word set to zero (§4.3.1
// "all unused vertex coordinate bits are set to zero"; the LSB always, as the extractor sees it
// overwritten). t: (n,) cell exponents (already clamped); W and u as above.
MatrixX3dR stego_quantize(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                          StegoPrecision p, const StegoFrame& fr);

// C with bit 0 of every word cleared (the marked mesh the extractor computes i' on).
MatrixX3dR stego_clear_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr);

// Message capacity in bits over the group leaders of an ordering (order, first from stego_order).
std::int64_t stego_capacity(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first);

// Replace the message bits of C (bits 1 .. min(k,W)-1) by nbits bits of `bits` (MSB-first bytes) in
// the order `order`; every member of a tie group (first == 0) gets its leader's bits. Returns C'.
MatrixX3dR stego_write_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                            StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                            const Eigen::Ref<const VectorXb>& first, const std::vector<std::uint8_t>& bits,
                            std::int64_t nbits);

// The inverse: nbits message bits (MSB-first bytes) read from the group leaders.
std::vector<std::uint8_t> stego_read_bits(const Eigen::Ref<const MatrixX3dR>& C, const Eigen::Ref<const VectorXi>& t,
                                          StegoPrecision p, const StegoFrame& fr, const Eigen::Ref<const VectorXi>& order,
                                          const Eigen::Ref<const VectorXb>& first, std::int64_t nbits);

// LSB slots (bit 0 of every word that has one) over the group leaders of the ordering.
std::int64_t stego_lsb_capacity(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                const Eigen::Ref<const VectorXb>& first, const Eigen::Ref<const VectorXi>& order);

// Write / read nbits of the LSB stream in the order `order` (leaders carry, members copy).
MatrixX3dR stego_write_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                           const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                           const std::vector<std::uint8_t>& bits, std::int64_t nbits);
std::vector<std::uint8_t> stego_read_lsb(const Eigen::Ref<const MatrixX3dR>& C, StegoPrecision p, const StegoFrame& fr,
                                         const Eigen::Ref<const VectorXi>& order, const Eigen::Ref<const VectorXb>& first,
                                         std::int64_t nbits);

}  // namespace meshmark
