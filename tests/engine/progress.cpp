// One monotone progress fraction per call (issue 24 item 3): the first
// geodesic query reports "prepare heat method" around the ordering and the two
// numeric factorizations, which report inside it (RunContext::sub), so the
// fractions a host's progress bar sees never go back.
#include <doctest/doctest.h>

#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

TEST_CASE("progress: the first geodesic query reports one monotone fraction, factorizations inside") {
  const Session s(make_icosphere(4));
  std::mutex mu;
  std::vector<double> f;
  std::vector<std::string> phases;
  RunContext ctx;
  ctx.progress = [&](double x, std::string_view phase) {
    std::lock_guard<std::mutex> lock(mu);
    f.push_back(x);
    phases.emplace_back(phase);
  };
  const std::vector<double> d = s.geodesic_distance(0, {}, ctx);
  REQUIRE(f.size() >= 4);
  CHECK(std::is_sorted(f.begin(), f.end()));
  CHECK(f.front() == 0.0);
  CHECK(f.back() == 1.0);
  CHECK(std::count(phases.begin(), phases.end(), "numeric factorization") >= 4);  // two factorizations, start and end each
  CHECK(std::all_of(f.begin(), f.end(), [](double x) { return x >= 0 && x <= 1; }));

  // RunContext::sub maps a phase's [0, 1] into the caller's range.
  RunContext outer;
  std::vector<double> g;
  outer.progress = [&](double x, std::string_view) { g.push_back(x); };
  const RunContext inner = outer.sub(0.5, 0.75).sub(0.5, 1.0);
  inner.report(0.0, "x");
  inner.report(1.0, "x");
  REQUIRE(g.size() == 2);
  CHECK(g[0] == 0.625);
  CHECK(g[1] == 0.75);
}
