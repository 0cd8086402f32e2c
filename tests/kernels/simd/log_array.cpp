// Tests for kernels/log_array: against std::log (relative 4e-16) on normal
// values over the whole exponent range, NaN for zero and negatives, std::log's
// answer for subnormals, infinity and NaN; lengths that are and are not whole
// SIMD batches.
#include "locus/kernels/simd/log_array.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace locus;

TEST_CASE("log_array equals std::log on normal values and handles the special ones") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(0.5, 2.0);
  std::uniform_int_distribution<int> ex(-1000, 1000);
  for (size_t n : {size_t{1}, size_t{7}, size_t{8}, size_t{24}, size_t{1001}}) {
    CAPTURE(n);
    std::vector<double> in(n), out(n);
    for (double& v : in) v = std::ldexp(mant(rng), ex(rng));
    log_array(in.data(), out.data(), n);
    double worst = 0;
    for (size_t k = 0; k < n; ++k) {
      const double ref = std::log(in[k]);
      worst = std::max(worst, std::abs(out[k] - ref) / std::max(std::abs(ref), 1e-300));
    }
    CHECK(worst <= 4e-16);
  }
  // Specials among normal values (a padded heat row ends in zeros).
  const double inf = std::numeric_limits<double>::infinity(), den = std::numeric_limits<double>::denorm_min();
  const std::vector<double> in{2.0, 0.0, -1.0, den, inf, std::nan(""), 1.0, 0.0, -0.0};
  std::vector<double> out(in.size());
  log_array(in.data(), out.data(), in.size());
  CHECK(out[0] == doctest::Approx(std::log(2.0)).epsilon(1e-15));
  CHECK(std::isnan(out[1]));
  CHECK(std::isnan(out[2]));
  CHECK(out[3] == std::log(den));
  CHECK(out[4] == inf);
  CHECK(std::isnan(out[5]));
  CHECK(out[6] == 0.0);
  CHECK(std::isnan(out[7]));
  CHECK(std::isnan(out[8]));
}
