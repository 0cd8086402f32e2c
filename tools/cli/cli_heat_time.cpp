// The heat-time options of the commands (cli_heat_time.hpp).
#include "tools/cli/cli_heat_time.hpp"

#include <charconv>
#include <cmath>

#include "locus/error.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

TimeSpec parse_time_spec(const std::string& text) { return parse_heat_time(text, "--t"); }

void add_heat_method_time(CLI::App* app, std::string& t, std::optional<double>& t_factor,
                          const std::string& default_text) {
  app->add_option("--t", t,
                  "Diffusion time: absolute (1e-3) or a multiple of h^2, h = mean edge length (h2, 4h2); default " +
                      default_text)
      ->check(non_empty());
  app->add_option("--t-factor", t_factor, "Deprecated spelling of --t: --t-factor C is --t Ch2");
}

void note_deprecated_t_factor(const std::optional<double>& t_factor) {
  if (t_factor) log("--t-factor is deprecated and will be removed; use --t " + format_number(*t_factor) + "h2");
}

double parse_h2_multiple(const std::string& text, const std::string& option, bool allow_zero) {
  double c = -1;
  const char* first = text.data();
  const char* last = first + text.size();
  auto [ptr, ec] = std::from_chars(first, last, c);
  if (ec != std::errc() || ptr != last || !(allow_zero ? c >= 0 : c > 0) || !std::isfinite(c))
    fail(ErrorCode::BadUsage, option + " must be a finite " + (allow_zero ? "number >= 0" : "positive number") +
                                  " (got '" + text + "')");
  return c;
}

}  // namespace locus::cli
