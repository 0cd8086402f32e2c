// Sets of small non-negative ids as plain bit arrays (64 ids per word): marking
// is one OR, and reading the set back yields the ids in ascending order for
// about n/64 word reads, which is cheaper than sorting once a set holds more
// than a few hundred ids (supernode sets, patch vertices and faces, submesh
// vertex sets).
#pragma once
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

namespace locus {

inline size_t bit_words(size_t n) { return (n + 63) / 64; }

inline void set_bit(std::span<uint64_t> bits, int32_t i) {
  bits[static_cast<uint32_t>(i) >> 6] |= uint64_t{1} << (i & 63);
}

// Appends the ids of the set bits to `out`, ascending.
template <class Ids>
inline void append_set_bits(std::span<const uint64_t> bits, Ids& out) {
  for (size_t w = 0; w < bits.size(); ++w)
    for (uint64_t b = bits[w]; b != 0; b &= b - 1) out.push_back(static_cast<int32_t>(w * 64 + std::countr_zero(b)));
}

}  // namespace locus
