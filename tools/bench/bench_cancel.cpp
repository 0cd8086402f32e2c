// `locus-bench cancel MESH`: how soon a C host's cancel takes effect (issue 24
// item 3). Not a test: at 416k vertices (armadillo --subdivide 2) it runs for
// minutes.
//
// Through the C API, as a host would: a session from arrays, then the first
// geodesic distance (ordering, symbolic analysis, numeric factorization of the
// two heat-method operators, solves) with a progress callback. A reference run
// records when each phase is reported. Then, per repeat and per cancel point
// (--at: fractions of the reference run's time), a fresh session starts the
// same call and the host "wants to cancel" at that time: the callback returns
// 1 from its next call on. The latency is the time from wanting to cancel to
// the call's return with LOCUS_CANCELLED (so it includes waiting for the next
// progress call, which is what a host feels). Medians per cancel point, with
// the phase reported last before the cancel. At the end the last cancelled
// session answers the query again, and the answer is compared bit for bit
// with the reference run's (the session stays usable).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
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
  std::string at = "0.1,0.3,0.5,0.7,0.9";  // cancel points, fractions of the reference run's time
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
  a.tris = m.face_vertices;
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

int run_cancel(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  const cli::Input in = cli::load_input(opt, ctx);
  const Arrays a = arrays_of(in.mesh);
  const int64_t n = in.mesh.num_vertices();
  std::vector<double> at;
  {
    std::stringstream ss(bo.at);
    for (std::string item; std::getline(ss, item, ',');) at.push_back(std::stod(item));
  }
  locus_run_options o = locus_run_options_default();
  o.threads = opt.threads;
  o.progress = on_progress;

  // Reference run: phases and the answer.
  Probe ref;
  o.user_data = &ref;
  std::vector<double> want(static_cast<size_t>(n)), got(static_cast<size_t>(n));
  locus_session* s = new_session(a);
  ref.start = Clock::now();
  if (locus_geodesic_distance_ex(s, 0, want.data(), &o) != LOCUS_OK)
    fail(ErrorCode::Internal, std::string("cancel bench: reference run failed: ") + locus_last_error_message());
  const double total_s = std::chrono::duration<double>(Clock::now() - ref.start).count();
  locus_session_destroy(s);
  cli::log("reference run: " + std::to_string(total_s) + " s");

  Json j;
  j["command"] = "cancel";
  j["input"] = cli::input_json(opt, in);
  j["reference_s"] = total_s;
  Json phases = Json::array();
  for (const auto& [t, name] : ref.phases) phases.push_back({{"phase", name}, {"start_s", t}});
  j["reference_phases"] = phases;

  Json points = Json::array();
  double worst_median = 0;
  s = nullptr;
  for (double f : at) {
    std::vector<double> lat;
    std::string phase;
    int cancelled = 0;
    for (int r = 0; r < bo.repeats; ++r) {
      locus_session_destroy(s);
      s = new_session(a);
      Probe p;
      p.cancel_after_s = f * total_s;
      o.user_data = &p;
      p.start = Clock::now();
      const locus_status st = locus_geodesic_distance_ex(s, 0, got.data(), &o);
      const double end_s = std::chrono::duration<double>(Clock::now() - p.start).count();
      if (st != LOCUS_CANCELLED || p.wanted_s < 0) continue;  // finished first (or no progress call came)
      ++cancelled;
      lat.push_back(1000.0 * (end_s - p.wanted_s));
      phase = p.last_phase;
    }
    const double med = median(lat);
    worst_median = std::max(worst_median, med);
    points.push_back({{"at", f}, {"cancel_after_s", f * total_s}, {"phase", phase}, {"cancelled", cancelled},
                      {"latency_ms", lat}, {"median_ms", med}});
    cli::log("cancel at " + std::to_string(f * total_s) + " s (" + phase + "): median " + std::to_string(med) + " ms");
  }
  j["cancel"] = points;
  j["worst_median_ms"] = worst_median;
  // The last cancelled session answers again, exactly as the reference.
  bool usable = false;
  if (s) {
    o.progress = nullptr;
    usable = locus_geodesic_distance_ex(s, 0, got.data(), &o) == LOCUS_OK &&
             std::memcmp(got.data(), want.data(), want.size() * sizeof(double)) == 0;
    locus_session_destroy(s);
  }
  j["session_usable_after_cancel"] = usable;
  cli::emit(opt, j, [&](std::ostream& os) {
    os << "cancel: " << n << " vertices, reference " << total_s << " s, worst median latency " << worst_median
       << " ms, session usable after cancel: " << (usable ? "yes" : "NO") << "\n";
    for (const auto& p : points)
      os << "  at " << p["cancel_after_s"] << " s (" << p["phase"].get<std::string>() << "): median " << p["median_ms"]
         << " ms\n";
  });
  return usable ? 0 : 4;
}

}  // namespace

void register_cancel_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add("cancel",
                            "Cancel latency of the first geodesic query (ordering, analysis, factorization) through "
                            "the C API's progress callback; the session answers correctly afterwards",
                            [bo](const cli::CommonOptions& opt, const RunContext& ctx) { return run_cancel(opt, *bo, ctx); });
  app->add_option("--repeats", bo->repeats, "Cancellations per cancel point (default 3)")->check(CLI::Range(1, 100));
  app->add_option("--at", bo->at, "Cancel points, fractions of the reference run's time (default 0.1,0.3,0.5,0.7,0.9)");
}

}  // namespace locus::bench
