// Vectorizable natural logarithm of an array (pure function over spans of doubles).
#pragma once
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace locus {

// out[k] = log(in[k]) for positive normal in[k] (NaN for in[k] <= 0), written so
// the compiler vectorizes it: the angle estimators take 7 to 19 logarithms per
// patch vertex, which scalar libm calls made a tenth of a query. Exponent and
// mantissa by bit operations, the mantissa reduced to [sqrt(1/2), sqrt(2)),
// log m = 2 atanh(z) with z = (m - 1) / (m + 1), |z| <= 0.1716, by its series to
// z^19 (truncation below 3e-17 relative); subnormals, infinities and NaNs go
// through std::log.
inline void log_array(const double* in, double* out, size_t n) {
  constexpr double kLn2 = 0.69314718055994530942;
  for (size_t k = 0; k < n; ++k) {
    const uint64_t bits = std::bit_cast<uint64_t>(in[k]);
    int64_t e = static_cast<int64_t>(bits >> 52) - 1023;
    double m = std::bit_cast<double>((bits & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull);
    const bool big = m > 1.4142135623730951;
    m = big ? 0.5 * m : m;
    e += big ? 1 : 0;
    const double z = (m - 1) / (m + 1), z2 = z * z;
    double p = 1.0 / 19;
    p = p * z2 + 1.0 / 17;
    p = p * z2 + 1.0 / 15;
    p = p * z2 + 1.0 / 13;
    p = p * z2 + 1.0 / 11;
    p = p * z2 + 1.0 / 9;
    p = p * z2 + 1.0 / 7;
    p = p * z2 + 1.0 / 5;
    p = p * z2 + 1.0 / 3;
    p = p * z2 + 1.0;
    out[k] = static_cast<double>(e) * kLn2 + 2 * z * p;
  }
  // Non-positive entries get their NaN in a second vectorized pass (a blend),
  // not by scalar stores: a caller reading out in vectors would stall on them
  // (store forwarding).
  for (size_t k = 0; k < n; ++k) out[k] = in[k] > 0 ? out[k] : std::numeric_limits<double>::quiet_NaN();
  // Subnormals, infinities and NaNs (rare): through std::log, after a
  // vectorizable check whether there are any.
  auto special = [](double v) {
    return v > 0 && !(v >= std::numeric_limits<double>::min() && v <= std::numeric_limits<double>::max());
  };
  bool any = false;
  for (size_t k = 0; k < n; ++k) any |= special(in[k]);
  if (!any) return;
  for (size_t k = 0; k < n; ++k)
    if (special(in[k])) out[k] = std::log(in[k]);
}

}  // namespace locus
