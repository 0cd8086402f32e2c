// Morton (Z-curve) order of points in 3D: points close in space get close
// positions in the order, so work done in runs of consecutive points touches
// compact regions (not from the thesis).
//
// Users: convex_hull_3d stores its points in Morton order (the points re-filed
// together after an insertion are then close in memory too), and Lloyd's CVT
// (pipelines/voronoi cvt_lloyd) seeds its batches of 8 cells in the Morton order
// of the sites, so a batch's neighborhoods overlap.
//
// A code interleaves the low 21 bits of three integer coordinates, bit b of x at
// bit 3b, of y at 3b + 1, of z at 3b + 2 (63 bits). The order sorts by code, ties
// by index, so it is a function of the codes alone.
//
// Thread safety: re-entrant; one workspace per thread.
#pragma once
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace locus {

// Bits per coordinate of a Morton code.
inline constexpr int kMortonBits = 21;

// The code of (x, y, z); bits above the low 21 of each coordinate are ignored.
uint64_t morton_code(uint64_t x, uint64_t y, uint64_t z);

// Codes of n points xyz[3i..3i+2] quantized to 21 bits in their bounding box:
// coordinate c maps (p_c - lo_c) / (hi_c - lo_c), clamped to [0, 1], to
// [0, 2^21 - 1] (truncated); an axis without extent maps to 0.
// BadUsage unless xyz.size() == 3 codes.size().
void morton_codes_in_box(std::span<const double> xyz, std::span<uint64_t> codes);

struct MortonWorkspace {
  std::vector<std::pair<uint64_t, int32_t>> keys;
};

// order[k]: index of the point with the k-th smallest (code, index).
// BadUsage unless order.size() == codes.size().
void morton_order(std::span<const uint64_t> codes, std::span<int32_t> order, MortonWorkspace& ws);

}  // namespace locus
