// Errors of a log map against the exact one (map_errors.hpp).
#include "tools/bench/map_errors.hpp"

#include <algorithm>
#include <cmath>

namespace locus::bench {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double wrap(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

Errors errors_of(const Surface& s, int32_t c, std::span<const int32_t> patch, std::span<const double> d,
                 std::span<const double> a, const std::vector<uint8_t>* mapped, Bands* bands) {
  double cs = 0, sn = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == c || (mapped && !(*mapped)[p])) continue;
    const double diff = a[p] - exact_angle(s, c, patch[p]);
    cs += std::cos(diff);
    sn += std::sin(diff);
  }
  const double delta = std::atan2(sn, cs);
  Errors e;
  double rmax = 0;
  if (bands)
    for (int32_t j : patch) rmax = std::max(rmax, s.exact_distance(c, j));
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == c || (mapped && !(*mapped)[p])) continue;
    const double r = s.exact_distance(c, patch[p]);
    const double ed = std::abs(d[p] - r), ea = std::abs(wrap(a[p] - exact_angle(s, c, patch[p]) - delta));
    e.ed += ed;
    e.ea += ea;
    ++e.count;
    if (bands && rmax > 0) {
      const int k = std::min(bands->size() - 1, static_cast<int>(r / rmax * bands->size()));
      bands->ed[k] += ed;
      bands->ea[k] += ea;
      ++bands->count[k];
    }
  }
  if (e.count > 0) {
    e.ed /= e.count;
    e.ea /= e.count;
  }
  return e;
}

}  // namespace locus::bench
