// Preview colours (kernels/include/locus/kernels/render/colour_map.hpp).
#include "locus/kernels/render/colour_map.hpp"

#include <algorithm>
#include <cmath>

namespace locus {

namespace {

Rgb hsv(double h, double s, double v) {
  h = (h - std::floor(h)) * 6;
  const int i = static_cast<int>(h) % 6;
  const double f = h - std::floor(h), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
  }
}

}  // namespace

Rgb scalar_colour(double s, int bands) {
  static const Rgb kStops[] = {{0.18, 0.10, 0.45}, {0.13, 0.35, 0.62}, {0.10, 0.58, 0.60},
                               {0.35, 0.76, 0.38}, {0.85, 0.87, 0.20}, {0.99, 0.91, 0.55}};
  constexpr int kLast = static_cast<int>(sizeof kStops / sizeof kStops[0]) - 1;
  s = std::clamp(s, 0.0, 1.0);
  const double x = s * kLast;
  const int i = std::min(static_cast<int>(x), kLast - 1);
  const double f = x - i;
  Rgb c{kStops[i][0] * (1 - f) + kStops[i + 1][0] * f, kStops[i][1] * (1 - f) + kStops[i + 1][1] * f,
        kStops[i][2] * (1 - f) + kStops[i + 1][2] * f};
  // The top value (s = 1) belongs to the last band, not to a band of its own.
  if (bands > 0 && std::min(static_cast<int64_t>(std::floor(s * bands)), int64_t{bands} - 1) % 2 == 1)
    for (double& v : c) v *= 0.82;
  return c;
}

Rgb label_colour(int64_t label) {
  if (label < 0) return kNoValueGrey;
  const double h = std::fmod(static_cast<double>(label) * 0.6180339887498949, 1.0);
  return hsv(h, label % 2 ? 0.55 : 0.8, label % 3 == 0 ? 0.95 : 0.8);
}

}  // namespace locus
