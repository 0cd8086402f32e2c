// The log map's estimator choices as the benchmarks spell them
// (--angle, --lattice, --recenter); "default" keeps the library's choice.
#pragma once
#include <optional>
#include <string>

#include "locus/error.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"

namespace locus::cli {

inline LogMapAngle parse_logmap_angle(const std::string& s) {
  if (s == "auto") return LogMapAngle::Auto;
  if (s == "log") return LogMapAngle::LogHeat;
  if (s == "two-ring") return LogMapAngle::LogHeatTwoRing;
  if (s == "average") return LogMapAngle::HeatAverage;
  fail(ErrorCode::BadUsage, "--angle must be auto, log, two-ring or average (got '" + s + "')");
}

inline std::optional<LatticeCorrection> parse_logmap_lattice(const std::string& s) {
  if (s == "default") return std::nullopt;
  if (s == "none") return LatticeCorrection::None;
  if (s == "star") return LatticeCorrection::Star;
  if (s == "ring") return LatticeCorrection::Ring;
  if (s == "path") return LatticeCorrection::Path;
  fail(ErrorCode::BadUsage, "--lattice must be none, star, ring or path (got '" + s + "')");
}

inline std::optional<bool> parse_logmap_recenter(const std::string& s) {
  if (s == "default") return std::nullopt;
  if (s == "on" || s == "off") return s == "on";
  fail(ErrorCode::BadUsage, "--recenter must be on or off (got '" + s + "')");
}

}  // namespace locus::cli
