// The heat-time grammar of every front end (engine/include/locus/engine/heat_time.hpp).
#include "locus/engine/heat_time.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "locus/core/format_significant.hpp"
#include "locus/error.hpp"

namespace locus {

HeatTime parse_heat_time(const std::string& text, const std::string& name) {
  auto bad = [&]() -> HeatTime {
    fail(ErrorCode::BadUsage, name + " '" + text +
                                  "': expected a positive time (0.001, 1e-3) or a multiple of h^2 (h2, 2h2, 500h2)");
  };
  HeatTime spec;
  std::string number = text;
  spec.times_h2 = false;
  if (number.size() >= 2 && number.compare(number.size() - 2, 2, "h2") == 0) {
    spec.times_h2 = true;
    number.resize(number.size() - 2);
  }
  if (number.empty()) {
    if (!spec.times_h2) return bad();
    spec.value = 1.0;  // "h2" alone
    return spec;
  }
  double v = 0;
  const char* first = number.data();
  const char* last = first + number.size();
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || !std::isfinite(v) || !(v > 0)) return bad();
  spec.value = v;
  return spec;
}

HeatTime heat_time_of(const std::string& t, const std::optional<double>& t_factor, const HeatTime& fallback) {
  if (t_factor) {
    if (!t.empty())
      fail(ErrorCode::BadUsage, "t and t_factor name one diffusion time; give t only (t_factor C is t Ch2)");
    if (!(*t_factor > 0) || !std::isfinite(*t_factor))
      fail(ErrorCode::BadUsage, "t_factor must be a finite positive number (got " + format_number(*t_factor) + ")");
    return HeatTime{*t_factor, true};
  }
  return t.empty() ? fallback : parse_heat_time(t);
}

double heat_time_factor(const HeatTime& time, double h) {
  if (time.times_h2) return time.value;
  if (!(h > 0) || !std::isfinite(h))
    fail(ErrorCode::BadInput, "mean edge length is " + format_number(h) + ": cannot express t as a multiple of h^2");
  return time.value / (h * h);
}

std::string format_number(double v) { return format_significant(v, 6); }

}  // namespace locus
