// Errors of a log map against the exact one on an analytic surface (thesis
// §6.7): E_d = mean |d - d_exact| and E_a = mean |angle - angle_exact - delta|
// (wrapped), delta the best global rotation (circular mean of the differences),
// both over the patch without the center; and the same by radius band.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/pipelines/geodesic/logmap.hpp"
#include "tools/bench/analytic_surfaces.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::bench {

// An angle wrapped to (-pi, pi].
double wrap(double a);

struct Maps {  // one map's output over a patch
  std::vector<double> d, a, u, v;
  void resize(size_t k) {
    d.resize(k);
    a.resize(k);
    u.resize(k);
    v.resize(k);
  }
  LogMapOutput out() { return {d, a, u, v}; }
};

struct Errors {
  double ed = 0, ea = 0;
  int64_t count = 0;
};

// Errors by radius band: band k holds the patch vertices whose exact distance
// is in [k, k + 1) * R / bands, R the patch's largest exact distance (the
// outermost band is "the rim"). Sums over every vertex of every center.
struct Bands {
  std::vector<double> ed, ea;
  std::vector<int64_t> count;
  explicit Bands(int k = 10) : ed(k, 0.0), ea(k, 0.0), count(k, 0) {}
  int size() const { return static_cast<int>(ed.size()); }
  double mean_ed(int a, int b) const {  // over bands [a, b)
    double s = 0;
    int64_t c = 0;
    for (int k = a; k < b; ++k) s += ed[k], c += count[k];
    return c > 0 ? s / c : 0.0;
  }
  double mean_ea(int a, int b) const {
    double s = 0;
    int64_t c = 0;
    for (int k = a; k < b; ++k) s += ea[k], c += count[k];
    return c > 0 ? s / c : 0.0;
  }
  cli::Json json() const {
    cli::Json rows = cli::Json::array();
    for (int k = 0; k < size(); ++k)
      rows.push_back(cli::Json{{"from", static_cast<double>(k) / size()}, {"to", static_cast<double>(k + 1) / size()},
                               {"E_d", count[k] > 0 ? ed[k] / count[k] : 0.0},
                               {"E_a", count[k] > 0 ? ea[k] / count[k] : 0.0}, {"vertices", count[k]}});
    const int n = size();
    const double inner = mean_ed(0, n / 2), outer = mean_ed(n - 1, n);
    return cli::Json{{"bands", rows}, {"E_d_inner_half", inner}, {"E_d_outer_band", outer},
                     {"E_d_outer_over_inner", inner > 0 ? outer / inner : 0.0}, {"E_a_inner_half", mean_ea(0, n / 2)},
                     {"E_a_outer_band", mean_ea(n - 1, n)}};
  }
};

// Mean errors over the patch minus the center; `mapped[p]` false skips p;
// `bands`, when given, also receives every vertex's errors by radius band.
Errors errors_of(const Surface& s, int32_t c, std::span<const int32_t> patch, std::span<const double> d,
                 std::span<const double> a, const std::vector<uint8_t>* mapped = nullptr, Bands* bands = nullptr);

}  // namespace locus::bench
