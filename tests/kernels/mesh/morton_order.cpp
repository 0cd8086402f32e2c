// Tests for kernels/mesh/morton_order.{hpp,cpp}. Oracle: a code built bit by bit
// (bit b of x, y, z to bits 3b, 3b + 1, 3b + 2) and a std::stable_sort of the
// indices by it; the quantization written out from its definition.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/morton_order.hpp"

using namespace locus;

namespace {

uint64_t interleave_bits(uint64_t x, uint64_t y, uint64_t z) {
  uint64_t code = 0;
  for (int b = 0; b < 21; ++b) {
    code |= ((x >> b) & 1u) << (3 * b);
    code |= ((y >> b) & 1u) << (3 * b + 1);
    code |= ((z >> b) & 1u) << (3 * b + 2);
  }
  return code;
}

std::vector<int32_t> order_by(const std::vector<uint64_t>& code) {
  std::vector<int32_t> idx(code.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](int32_t a, int32_t b) { return code[a] < code[b]; });
  return idx;
}

}  // namespace

TEST_CASE("morton code: interleaves the low 21 bits of each coordinate") {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 2000; ++i) {
    const uint64_t x = rng(), y = rng(), z = rng();
    CHECK(morton_code(x, y, z) == interleave_bits(x, y, z));
  }
  CHECK(morton_code(1, 0, 0) == 1);
  CHECK(morton_code(0, 1, 0) == 2);
  CHECK(morton_code(0, 0, 1) == 4);
  CHECK(morton_code(0x1fffff, 0x1fffff, 0x1fffff) == (uint64_t(1) << 63) - 1);
  CHECK(morton_code(uint64_t(1) << 21, 0, 0) == 0);  // above the 21 bits: ignored
}

TEST_CASE("morton order: sorted by code, ties by index") {
  std::mt19937_64 rng(9);
  std::vector<uint64_t> code(3000);
  for (uint64_t& c : code) c = rng() % 500;  // many ties
  std::vector<int32_t> order(code.size());
  MortonWorkspace ws;
  morton_order(code, order, ws);
  CHECK(order == order_by(code));
  std::vector<int32_t> empty;
  morton_order(std::vector<uint64_t>{}, empty, ws);
  std::vector<int32_t> wrong(2);
  CHECK_THROWS_AS(morton_order(code, wrong, ws), Error);
}

TEST_CASE("morton codes in the bounding box: quantized to 21 bits per axis, flat axes at 0") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 7.0);
  const size_t n = 400;
  std::vector<double> p(3 * n);
  for (size_t i = 0; i < n; ++i) {
    p[3 * i] = u(rng);
    p[3 * i + 1] = u(rng) * 1e-3;
    p[3 * i + 2] = 0.25;  // no extent along z
  }
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c) {
      lo[c] = std::min(lo[c], p[3 * i + c]);
      hi[c] = std::max(hi[c], p[3 * i + c]);
    }
  std::vector<uint64_t> code(n);
  morton_codes_in_box(p, code);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t qx = static_cast<uint64_t>((p[3 * i] - lo[0]) / (hi[0] - lo[0]) * 2097151.0);
    const uint64_t qy = static_cast<uint64_t>((p[3 * i + 1] - lo[1]) / (hi[1] - lo[1]) * 2097151.0);
    CHECK(code[i] == interleave_bits(qx, qy, 0));
  }
  // The box's corners get the extreme codes.
  const std::vector<double> corners = {0, 0, 0, 1, 1, 1, 0.5, 0.5, 0.5};
  std::vector<uint64_t> cc(3);
  morton_codes_in_box(corners, cc);
  CHECK(cc[0] == 0);
  CHECK(cc[1] == (uint64_t(1) << 63) - 1);
  CHECK(cc[2] == interleave_bits(1048575, 1048575, 1048575));
  std::vector<uint64_t> wrong(5);
  CHECK_THROWS_AS(morton_codes_in_box(p, wrong), Error);
}
