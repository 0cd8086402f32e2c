// The one heat-time grammar of every command: --t T, an absolute time
// ("0.001", "1e-3") or a multiple of h^2, h = mean edge length ("h2", "2h2",
// "500h2"), as geometry-central's tCoef (locus/engine/heat_time.hpp). The
// heat-method commands (geodesic, logmap) also accept their older
// --t-factor C, meaning --t Ch2, as a deprecated alias (a note on stderr).
#pragma once
#include <optional>
#include <string>

#include "locus/engine/heat_time.hpp"
#include "tools/cli/cli_command_table.hpp"

namespace locus::cli {

using TimeSpec = HeatTime;

// Throws Error(BadUsage) naming --t and the text unless it is a finite positive time.
TimeSpec parse_time_spec(const std::string& text);

// A deprecated spelling's bare number C (a multiple of h^2): Error(BadUsage)
// naming `option` unless it is finite and > 0 (>= 0 with allow_zero).
double parse_h2_multiple(const std::string& text, const std::string& option, bool allow_zero);

// Adds --t (bound to `t`) and the deprecated --t-factor (bound to `t_factor`)
// of a heat-method request; `default_text` completes --t's help.
void add_heat_method_time(CLI::App* app, std::string& t, std::optional<double>& t_factor,
                          const std::string& default_text);
// The note on stderr for the deprecated --t-factor, when it was given.
void note_deprecated_t_factor(const std::optional<double>& t_factor);

}  // namespace locus::cli
