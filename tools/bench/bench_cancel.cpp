// `locus-bench cancel MESH`: how soon a C host's cancel takes effect. Not a
// test: at 416k vertices (armadillo --subdivide 2) it runs for minutes.
//
// Through the C API, as a host would: a session from arrays, then the first
// call (--call geodesic: ordering, symbolic analysis, numeric factorization of
// the two heat-method operators, solves; --call cvt: the cells' operator, then
// the Lloyd iterations) with a progress callback. A reference run records when
// each phase is reported. Then, per sample, a fresh session starts the same
// call and the host "wants to cancel" at a time drawn uniformly over the
// reference run (--random N samples, seeded), or at the given fractions of it
// (--at, --repeats each): the callback returns 1 from its next call on. The
// latency is the time from wanting to cancel to the call's return with
// LOCUS_CANCELLED (so it includes waiting for the next progress call, which is
// what a host feels). Median and maximum per phase (the phase reported last
// before the cancel) and overall. At the end the last cancelled session
// answers the query again, compared bit for bit with the reference run's
// answer (the session stays usable).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "locus/locus.h"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using Clock = std::chrono::steady_clock;

struct Options {
  int repeats = 3;
  std::string at;      // cancel points, fractions of the reference run's time (instead of --random)
  int random = 15;     // cancel times drawn uniformly over the reference run
  uint64_t seed = 1;
  std::string call = "geodesic";  // or cvt
  int sites = 1000, iters = 3;    // cvt
};

struct Probe {
  Clock::time_point start;
  double cancel_after_s = -1;  // < 0: never cancel
  std::mutex mu;
  std::string last_phase;
  std::vector<std::pair<double, std::string>> phases;  // (seconds, phase) of each new phase
  double wanted_s = -1;                                // when the cancel was asked for (first call after cancel_after_s)
};

int on_progress(double /*fraction*/, const char* phase, void* user) {
  Probe& p = *static_cast<Probe*>(user);
  std::lock_guard<std::mutex> lock(p.mu);
  const double t = std::chrono::duration<double>(Clock::now() - p.start).count();
  if (p.cancel_after_s >= 0 && t >= p.cancel_after_s) {
    if (p.wanted_s < 0) p.wanted_s = p.cancel_after_s;
    return 1;
  }
  if (p.last_phase != phase) {
    p.last_phase = phase;
    p.phases.emplace_back(t, phase);
  }
  return 0;
}

struct Arrays {
  std::vector<double> xyz;
  std::vector<int32_t> tris;
};

Arrays arrays_of(const Mesh& m) {
  Arrays a;
  for (int32_t i = 0; i < m.num_vertices(); ++i) a.xyz.insert(a.xyz.end(), {m.x[i], m.y[i], m.z[i]});
  a.tris.assign(m.face_vertices.begin(), m.face_vertices.end());
  return a;
}

locus_session* new_session(const Arrays& a) {
  locus_session* s = nullptr;
  if (locus_session_create(a.xyz.data(), static_cast<int64_t>(a.xyz.size() / 3), a.tris.data(),
                           static_cast<int64_t>(a.tris.size() / 3), &s) != LOCUS_OK)
    fail(ErrorCode::BadInput, std::string("cancel bench: ") + locus_last_error_message());
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The call under test; the answer goes to out (geodesic: distances; cvt: labels as doubles).
locus_status run_call(locus_session* s, const Options& bo, std::vector<double>& out, const locus_run_options* o) {
  if (bo.call == "cvt") {
    std::vector<int32_t> labels(out.size());
    const locus_status st = locus_cvt_ex(s, bo.sites, bo.iters, 1, labels.data(), nullptr, o);
    std::copy(labels.begin(), labels.end(), out.begin());
    return st;
  }
  return locus_geodesic_distance_ex(s, 0, out.data(), o);
}

struct Sample {
  double at_s, latency_ms;
  std::string phase;
};

Json stats_json(const std::vector<double>& lat) {
  const double med = median(lat);
  const double max = lat.empty() ? -1 : *std::max_element(lat.begin(), lat.end());
  return Json{{"samples", lat.size()}, {"median_ms", med}, {"max_ms", max}};
}

int run_cancel(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  if (bo.call != "geodesic" && bo.call != "cvt") fail(ErrorCode::BadUsage, "--call must be geodesic or cvt");
  const cli::Input in = cli::load_input(opt, ctx);
  const Arrays a = arrays_of(in.mesh);
  const int64_t n = in.mesh.num_vertices();
  locus_run_options o = locus_run_options_default();
  o.threads = opt.threads;
  o.progress = on_progress;

  // Reference run: phases and the answer.
  Probe ref;
  o.user_data = &ref;
  std::vector<double> want(static_cast<size_t>(n)), got(static_cast<size_t>(n));
  locus_session* s = new_session(a);
  ref.start = Clock::now();
  if (run_call(s, bo, want, &o) != LOCUS_OK)
    fail(ErrorCode::Internal, std::string("cancel bench: reference run failed: ") + locus_last_error_message());
  const double total_s = std::chrono::duration<double>(Clock::now() - ref.start).count();
  locus_session_destroy(s);
  cli::log("reference run: " + std::to_string(total_s) + " s");

  // Cancel times: fractions of the reference run (--at, each --repeats times) or uniform draws.
  std::vector<double> at_s;
  if (!bo.at.empty()) {
    std::stringstream ss(bo.at);
    for (std::string item; std::getline(ss, item, ',');)
      for (int r = 0; r < bo.repeats; ++r) at_s.push_back(std::stod(item) * total_s);
  } else {
    std::mt19937_64 rng(bo.seed);
    std::uniform_real_distribution<double> u(0.0, total_s);
    for (int k = 0; k < bo.random; ++k) at_s.push_back(u(rng));
  }

  Json j;
  j["command"] = "cancel";
  j["call"] = bo.call;
  j["input"] = cli::input_json(opt, in);
  j["reference_s"] = total_s;
  Json phases = Json::array();
  for (const auto& [t, name] : ref.phases) phases.push_back({{"phase", name}, {"start_s", t}});
  j["reference_phases"] = phases;

  std::vector<Sample> samples;
  int finished_first = 0;
  s = nullptr;
  for (const double t : at_s) {
    locus_session_destroy(s);
    s = new_session(a);
    Probe p;
    p.cancel_after_s = t;
    o.user_data = &p;
    p.start = Clock::now();
    const locus_status st = run_call(s, bo, got, &o);
    const double end_s = std::chrono::duration<double>(Clock::now() - p.start).count();
    if (st != LOCUS_CANCELLED || p.wanted_s < 0) {  // finished first (or no progress call came)
      ++finished_first;
      continue;
    }
    samples.push_back({t, 1000.0 * (end_s - p.wanted_s), p.last_phase});
    cli::log("cancel at " + std::to_string(t) + " s (" + p.last_phase + "): " +
             std::to_string(samples.back().latency_ms) + " ms");
  }
  std::map<std::string, std::vector<double>> by_phase;
  std::vector<double> all;
  Json points = Json::array();
  for (const Sample& x : samples) {
    by_phase[x.phase].push_back(x.latency_ms);
    all.push_back(x.latency_ms);
    points.push_back({{"cancel_after_s", x.at_s}, {"phase", x.phase}, {"latency_ms", x.latency_ms}});
  }
  Json per_phase = Json::object();
  for (const auto& [name, lat] : by_phase) per_phase[name] = stats_json(lat);
  j["cancel"] = points;
  j["per_phase"] = per_phase;
  j["overall"] = stats_json(all);
  j["finished_before_cancel"] = finished_first;
  // The last cancelled session answers again, exactly as the reference.
  bool usable = false;
  if (s) {
    o.progress = nullptr;
    usable = run_call(s, bo, got, &o) == LOCUS_OK &&
             std::memcmp(got.data(), want.data(), want.size() * sizeof(double)) == 0;
    locus_session_destroy(s);
  }
  j["session_usable_after_cancel"] = usable;
  cli::emit(opt, j, [&](std::ostream& os) {
    os << "cancel " << bo.call << ": " << n << " vertices, reference " << total_s << " s, " << samples.size()
       << " cancelled, " << finished_first << " finished first, session usable after cancel: "
       << (usable ? "yes" : "NO") << "\n";
    for (const auto& [name, st] : per_phase.items())
      os << "  " << name << ": " << st["samples"] << " samples, median " << st["median_ms"] << " ms, max "
         << st["max_ms"] << " ms\n";
    os << "  overall: median " << j["overall"]["median_ms"] << " ms, max " << j["overall"]["max_ms"] << " ms\n";
  });
  return usable ? 0 : 4;
}

}  // namespace

void register_cancel_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add("cancel",
                            "Cancel latency of the first geodesic or cvt call (ordering, analysis, factorization, "
                            "iterations) through the C API's progress callback, per phase; the session answers "
                            "correctly afterwards",
                            [bo](const cli::CommonOptions& opt, const RunContext& ctx) { return run_cancel(opt, *bo, ctx); });
  app->add_option("--random", bo->random, "Cancel times drawn uniformly over the reference run (default 15)")
      ->check(CLI::Range(1, 1000));
  app->add_option("--cancel-seed", bo->seed, "Seed of the cancel times (default 1)");
  app->add_option("--at", bo->at, "Cancel points instead, fractions of the reference run's time (e.g. 0.1,0.5)");
  app->add_option("--repeats", bo->repeats, "Cancellations per --at point (default 3)")->check(CLI::Range(1, 100));
  app->add_option("--call", bo->call, "The call cancelled: geodesic (default) or cvt");
  app->add_option("--sites", bo->sites, "cvt: sites (default 1000)")->check(CLI::Range(1, 1 << 30));
  app->add_option("--iters", bo->iters, "cvt: Lloyd iterations (default 3)")->check(CLI::Range(0, 10000));
}

}  // namespace locus::bench
