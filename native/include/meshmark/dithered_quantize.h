// meshmark: the dithered quantizer of thesis ch. 3 and 4: keep the t most significant bits of every
// coordinate word and replace the less significant bits by random bits.
#pragma once
#include "meshmark/mesh.h"

namespace meshmark {

enum class DitherWord {
  Fixed32,  // ch. 4: 32-bit unsigned fixed point in the bounding cube: lo = per-axis min, L = the
            // largest extent, q = min(floor((x - lo) / L * 2^32), 2^32 - 1), x' = lo + L q' / 2^32
  Float64,  // ch. 3 (3.2.1): the IEEE-754 binary64 bit pattern, sign first, t in 0..64
};

// Deterministic core: t (n,) bits kept per vertex (the same for its 3 coordinates); words (n,3) the
// replacement bits (their low 64 - t, or 32 - t, bits are used). MeshError if a t is out of range
// (0..32 for Fixed32, 0..64 for Float64) or shapes differ. Float64 with t <= 12 may produce
// non-finite values (random exponent bits), as the thesis' t = 0 end of its curve.
MatrixX3dR dither_bits(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXi>& t,
                       const Eigen::Ref<const Eigen::Matrix<std::uint64_t, Eigen::Dynamic, 3, Eigen::RowMajor>>& words,
                       DitherWord word);

// dither_bits with words drawn by Rng(seed).bits(), row by row (x, y, z).
MatrixX3dR dithered_quantize(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const VectorXi>& t,
                             std::uint64_t seed, DitherWord word);

}  // namespace meshmark
