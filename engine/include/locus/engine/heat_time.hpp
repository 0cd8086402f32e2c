// The diffusion time of every heat operator as the front ends spell it: an
// absolute time ("0.001", "1e-3", in units of length^2) or a multiple of h^2,
// h the mean edge length ("h2", "4h2", "500h2"), as geometry-central's tCoef
// (thesis §3.3, §6.4: t scales with h^2 so that the heat spreads over the
// same number of edges at any resolution).
//
// The heat-method requests (geodesic, logmap) also take the older spelling
// t_factor = C, meaning "Ch2"; heat_time_of() resolves the two.
#pragma once
#include <optional>
#include <string>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API HeatTime {
  double value = 1.0;
  bool times_h2 = true;  // value is a multiple of h^2
  double resolve(double h) const { return times_h2 ? value * h * h : value; }
};

// Error(BadUsage) naming `name` and the text unless it is a finite positive
// time in the grammar above.
LOCUS_API HeatTime parse_heat_time(const std::string& text, const std::string& name = "t");

// The time of a request with the fields `t` (text, "" = not given) and
// `t_factor` (a multiple of h^2, empty = not given): Error(BadUsage) when both
// are given or t_factor is not finite and > 0; `fallback` when neither is.
LOCUS_API HeatTime heat_time_of(const std::string& t, const std::optional<double>& t_factor, const HeatTime& fallback);

// The time as a multiple of h^2 on a mesh of mean edge length h (the heat
// method's t_factor): Error(BadInput) when h is not finite and positive.
LOCUS_API double heat_time_factor(const HeatTime& time, double h);

// %.6g of a number, as every message and report of locus prints one.
LOCUS_API std::string format_number(double v);

}  // namespace locus
LOCUS_API_END
