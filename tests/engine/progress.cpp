// One monotone progress fraction per call: the first
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
  // The two factorizations run side by side; the heat one reports for both (start and end).
  CHECK(std::count(phases.begin(), phases.end(), "numeric factorization") >= 2);
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

namespace {

// Every report of one call: fractions in [0, 1], never going back, the last one 1.
struct Recorder {
  std::mutex mu;
  std::vector<double> f;
  std::vector<std::string> phases;
  RunContext ctx() {
    RunContext c;
    c.progress = [this](double x, std::string_view phase) {
      std::lock_guard<std::mutex> lock(mu);
      f.push_back(x);
      phases.emplace_back(phase);
    };
    return c;
  }
  void check(const char* call, size_t min_distinct) {
    CAPTURE(call);
    REQUIRE(!f.empty());
    CHECK(std::is_sorted(f.begin(), f.end()));
    CHECK(f.front() >= 0.0);
    CHECK(f.back() == 1.0);
    std::vector<double> distinct = f;
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    CHECK(distinct.size() >= min_distinct);  // reports inside the call, not only its end
    f.clear();
    phases.clear();
  }
};

}  // namespace

TEST_CASE("progress: every long Session call reports one monotone fraction that reaches 1") {
  const Session s(make_icosphere(3));
  Recorder r;
  // First calls build their operators (ordering, analysis, factorization inside the call's range);
  // second calls find them cached and report the query alone.
  for (int round = 0; round < 2; ++round) {
    CAPTURE(round);
    s.geodesic_distance(0, {}, r.ctx());
    r.check("geodesic_distance", round == 0 ? 4 : 1);
    s.logmap(3, 0.3, {}, r.ctx());
    r.check("logmap", 1);
    const std::vector<MeshPoint> g{MeshPoint::at_vertex(0), MeshPoint::at_vertex(200), MeshPoint::at_vertex(400)};
    s.voronoi(g, {}, r.ctx());
    r.check("voronoi", round == 0 ? 4 : 2);
    s.skinning_weights(g, {}, r.ctx());
    r.check("skinning_weights", 1);
    s.cvt(30, 4, 7, r.ctx());
    r.check("cvt", 4);  // the Lloyd iterations report inside the call's range, each after the factor's share
    const std::vector<HeatQuery> times{{1.0, 0.0}, {4.0, 0.0}};
    s.heat_kernel_signature(times, {}, DiagonalMethod::Subset, r.ctx());
    r.check("heat_kernel_signature", 2);
    const std::vector<int32_t> src{0, 1}, tgt{5, 6, 7};
    s.heat_exchange(src, tgt, {}, r.ctx());
    r.check("heat_exchange", 1);
    PatchParamRequest pr;
    pr.center = 10;
    pr.fraction = 0.2;
    s.parameterize_patch(pr, r.ctx());
    r.check("parameterize_patch", 1);
    s.perfect_laplacian(PerfectLaplacianRequest{}, r.ctx());
    r.check("perfect_laplacian", 2);
  }
}
