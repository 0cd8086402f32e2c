// Morton (Z-curve) codes and order (kernels/include/locus/kernels/mesh/morton_order.hpp).
#include "locus/kernels/mesh/morton_order.hpp"

#include <algorithm>
#include <cmath>

#include "locus/error.hpp"

namespace locus {

namespace {

// The low 21 bits of x spread to every third bit of 63: five shift-and-mask
// rounds, each halving the width of the bit groups moved (16, 8, 4, 2, 1 bits).
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

uint64_t morton_code(uint64_t x, uint64_t y, uint64_t z) {
  return spread_bits(x) | spread_bits(y) << 1 | spread_bits(z) << 2;
}

void morton_codes_in_box(std::span<const double> xyz, std::span<uint64_t> codes) {
  const size_t n = codes.size();
  if (xyz.size() != 3 * n) fail(ErrorCode::BadUsage, "morton codes: expected 3 coordinates per point");
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], xyz[3 * i + c]);
      hi[c] = std::max(hi[c], xyz[3 * i + c]);
    }
  constexpr double kTop = static_cast<double>((uint64_t(1) << kMortonBits) - 1);
  for (size_t i = 0; i < n; ++i) {
    uint64_t q[3];
    for (int c = 0; c < 3; ++c) {
      const double ext = hi[c] - lo[c];
      const double f = ext > 0 ? (xyz[3 * i + c] - lo[c]) / ext : 0.0;
      q[c] = static_cast<uint64_t>(std::clamp(f, 0.0, 1.0) * kTop);
    }
    codes[i] = morton_code(q[0], q[1], q[2]);
  }
}

void morton_order(std::span<const uint64_t> codes, std::span<int32_t> order, MortonWorkspace& ws) {
  const size_t n = codes.size();
  if (order.size() != n) fail(ErrorCode::BadUsage, "morton order: one output entry per code expected");
  ws.keys.resize(n);
  for (size_t i = 0; i < n; ++i) ws.keys[i] = {codes[i], static_cast<int32_t>(i)};
  std::sort(ws.keys.begin(), ws.keys.end());
  for (size_t k = 0; k < n; ++k) order[k] = ws.keys[k].second;
}

}  // namespace locus
