// `locus-bench stress MESH`: concurrency, memory and cancellation stress of one
// locus::Session. Not a test: it runs for minutes.
//
// 1. Reference answers: a seeded set of queries — heat geodesic distance, heat
//    log maps, heat values by subset solves, ROI deformations (factor-once
//    submesh updates on copies of the positions) — each computed alone, one
//    after the other, with a single thread.
// 2. Warm-up: every query once more from --threads concurrent callers, so
//    every cache, arena and thread-local workspace exists; RSS is read then
//    (rss_start_mb).
// 3. For --seconds, --threads callers pick queries at random (each with a
//    RunContext of 1 or 2 threads, alternating) and compare every result bit
//    for bit with its reference; RSS is sampled once a second; rss_end_mb at
//    the end. A result that differs is a mismatch, an exception an error.
// 4. Cancellation: long pipelines (a CVT with many Lloyd steps on the Session;
//    the numeric factorization of the heat operator) are started, their cancel
//    flag is raised after a delay, and the time until the call returns with
//    Error(Cancelled) is the latency (max over repeats: cancel_latency_ms).
//
// `--big`: instead of all that, load, factor and answer one log-map query (the
// 5M-vertex check: armadillo with --subdivide 4) and report the phases and the
// peak resident memory (getrusage ru_maxrss).
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>
#include <thread>
#include <unistd.h>

#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/session.hpp"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;
using Clock = std::chrono::steady_clock;

struct Options {
  double seconds = 60;
  double fraction = 0.01;    // log-map disk size, fraction of the vertices
  double roi_fraction = 0.02;  // deformation region
  int queries_per_kind = 8;
  int cancel_repeats = 5;
  std::string kinds = "geodesic,logmap,heat_values,deform";  // query kinds in the mix
  bool big = false;
};

double rss_mb() {
  std::ifstream in("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  in >> pages_total >> pages_resident;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The query kinds, with their seeded arguments and reference answers.
enum class Kind { Geodesic, LogMap, HeatValues, Deform };
const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Geodesic: return "geodesic";
    case Kind::LogMap: return "logmap";
    case Kind::HeatValues: return "heat_values";
    case Kind::Deform: return "deform";
  }
  return "?";
}

struct Query {
  explicit Query(Kind k, int32_t v = 0) : kind(k), vertex(v) {}
  Kind kind;
  int32_t vertex;                          // geodesic source / log-map center
  std::vector<int32_t> sources, targets;   // heat values
  DeformRequest deform;
  std::vector<double> answer;              // flattened result (reference or candidate)
  std::vector<int32_t> answer_ids;         // log-map patch
};

// Runs q on the session and stores the flattened result in out.
void run_query(const Session& s, const Query& q, double fraction, const RunContext& ctx, std::vector<double>& out,
               std::vector<int32_t>& ids) {
  out.clear();
  ids.clear();
  switch (q.kind) {
    case Kind::Geodesic:
      out = s.geodesic_distance(q.vertex, HeatQuery{}, ctx);
      break;
    case Kind::LogMap: {
      LogMapResult r = s.logmap(q.vertex, fraction, HeatQuery{}, ctx);
      ids.assign(r.patch.begin(), r.patch.end());
      for (const auto* v : {&r.distance, &r.angle, &r.u, &r.v}) out.insert(out.end(), v->begin(), v->end());
      break;
    }
    case Kind::HeatValues:
      out = s.heat_values(q.sources, q.targets, HeatQuery{}, ctx);
      break;
    case Kind::Deform: {
      DeformResult r = s.deform(q.deform, ctx);
      out = std::move(r.xyz);
      out.push_back(r.residual);
      out.push_back(r.columns_updated_fraction);
      ids = {r.roi_size, r.free_size, r.refinement_steps};
      break;
    }
  }
}

// Seeded query set: queries_per_kind of each kind.
std::vector<Query> make_queries(const Session& s, const Options& bo, uint64_t seed) {
  const int32_t n = s.num_vertices();
  const int q = bo.queries_per_kind;
  const std::vector<double> r = cli::random_vector(static_cast<size_t>(q) * 200, seed);
  size_t next = 0;
  auto vertex = [&] { return std::min(n - 1, static_cast<int32_t>((r[next++ % r.size()] + 1.0) * 0.5 * n)); };
  std::vector<Query> out;
  auto wanted = [&](Kind k) { return ("," + bo.kinds + ",").find(std::string(",") + kind_name(k) + ",") != std::string::npos; };
  for (int i = 0; i < q && wanted(Kind::Geodesic); ++i) out.emplace_back(Kind::Geodesic, vertex());
  for (int i = 0; i < q && wanted(Kind::LogMap); ++i) out.emplace_back(Kind::LogMap, vertex());
  for (int i = 0; i < q && wanted(Kind::HeatValues); ++i) {
    Query h(Kind::HeatValues);
    for (int k = 0; k < 4; ++k) h.sources.push_back(vertex());
    for (int k = 0; k < 64; ++k) h.targets.push_back(vertex());
    out.push_back(std::move(h));
  }
  const double h = s.mean_edge_length();
  for (int i = 0; i < q && wanted(Kind::Deform); ++i) {
    Query d(Kind::Deform);
    d.deform.roi_seed = vertex();
    d.deform.roi_fraction = bo.roi_fraction;
    d.deform.handle_vertex = d.deform.roi_seed;  // the seed is always inside its own ROI
    d.deform.handle_ring = 1;
    d.deform.offset = {2 * h * r[next++ % r.size()], 2 * h * r[next++ % r.size()], 2 * h};
    d.deform.energy = i % 2 ? DeformEnergyKind::Bilaplacian : DeformEnergyKind::Laplacian;
    out.push_back(std::move(d));
  }
  if (out.empty()) fail(ErrorCode::BadUsage, "--kinds '" + bo.kinds + "' names no query kind (geodesic, logmap, heat_values, deform)");
  return out;
}

struct Counters {
  std::atomic<int64_t> queries{0}, mismatches{0}, errors{0};
  std::mutex mu;
  Json examples = Json::array();  // first few mismatches and errors, for the report
  void note(const std::string& what) {
    std::lock_guard<std::mutex> lock(mu);
    if (examples.size() < 10) examples.push_back(what);
  }
};

// One caller: runs queries (in order when `sweep`, else seeded random picks)
// until `stop`, checking each against its reference.
void caller(const Session& s, const std::vector<Query>& qs, double fraction, int id, bool sweep,
            const std::atomic<bool>& stop, const RunContext& outer, Counters& c) {
  std::vector<double> out;
  std::vector<int32_t> ids;
  uint64_t state = 0x9e3779b97f4a7c15ull * static_cast<uint64_t>(id + 1);
  for (size_t k = 0; !stop.load(std::memory_order_relaxed) && !outer.cancelled(); ++k) {
    size_t i;
    if (sweep) {
      if (k >= qs.size()) break;
      i = (k + static_cast<size_t>(id) * 7) % qs.size();  // callers start at different queries
    } else {
      state ^= state << 13; state ^= state >> 7; state ^= state << 17;  // xorshift64
      i = static_cast<size_t>(state % qs.size());
    }
    RunContext ctx;
    ctx.threads = 1 + static_cast<int>(k % 2);  // results must not depend on the thread count
    ctx.cancel = outer.cancel;
    try {
      run_query(s, qs[i], fraction, ctx, out, ids);
      c.queries.fetch_add(1);
      if (!same_bits(out, qs[i].answer) || ids != qs[i].answer_ids) {
        c.mismatches.fetch_add(1);
        c.note(std::string("mismatch: ") + kind_name(qs[i].kind) + " query " + std::to_string(i) + " with " +
               std::to_string(ctx.threads) + " threads");
      }
    } catch (const std::exception& e) {
      if (outer.cancelled()) break;
      c.errors.fetch_add(1);
      c.note(std::string("error: ") + kind_name(qs[i].kind) + " query " + std::to_string(i) + ": " + e.what());
    }
  }
}

// Starts `body(ctx)` on a thread, raises its cancel flag after `delay_ms`, and
// returns the milliseconds from raising the flag to the call's return with
// Error(Cancelled); a negative value when it finished before the flag or failed
// otherwise (the reason in `why`).
template <typename Body>
double cancel_latency(Body body, double delay_ms, std::string& why) {
  std::atomic<bool> flag{false};
  std::atomic<int64_t> returned_ns{0};
  std::atomic<int> outcome{0};  // 1 cancelled, 2 finished, 3 other error
  std::string error;
  std::thread t([&] {
    RunContext ctx;
    ctx.cancel = &flag;
    try {
      body(ctx);
      outcome = 2;
    } catch (const Error& e) {
      outcome = e.code() == ErrorCode::Cancelled ? 1 : 3;
      if (outcome == 3) error = e.what();
    } catch (const std::exception& e) {
      outcome = 3;
      error = e.what();
    }
    returned_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
  });
  std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(delay_ms));
  const int64_t raised_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
  flag.store(true);
  t.join();
  if (outcome == 2) { why = "finished before the cancel flag was raised"; return -1; }
  if (outcome == 3) { why = "failed: " + error; return -1; }
  return static_cast<double>(returned_ns.load() - raised_ns) * 1e-6;
}

int run_big(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  Json j;
  j["command"] = "stress";
  j["mode"] = "big";
  Stopwatch sw;
  const cli::Input in = cli::load_input(opt, ctx);
  j["input"] = cli::input_json(opt, in);
  j["load_s"] = in.load_s;
  j["subdivide_s"] = in.subdivide_s;
  j["rss_after_load_mb"] = rss_mb();
  cli::log("loaded " + std::to_string(in.mesh.num_vertices()) + " vertices; estimating the factor");

  // The factor's size, from the same analysis the Session runs.
  sw.restart();
  {
    const CscMatrix A = heat_operator(in.mesh, 1.0);
    auto S = analyze(A, order_matrix(A));
    const FactorMemoryEstimate e = estimate_factor_memory(*S, ctx.threads > 0 ? ctx.threads : 2);
    j["nnz_L"] = S->nnz_L;
    j["factor_estimate_gib"] = static_cast<double>(e.total_bytes) / (1024.0 * 1024.0 * 1024.0);
    j["analyze_s"] = sw.seconds();
  }
  sw.restart();
  Session s(in.mesh);
  j["session_s"] = sw.seconds();
  sw.restart();
  RunContext qctx = ctx;
  s.prepare_heat(HeatQuery{}, qctx);
  j["prepare_heat_s"] = sw.seconds();
  j["rss_after_factor_mb"] = rss_mb();
  sw.restart();
  const LogMapResult r = s.logmap(s.num_vertices() / 2, bo.fraction, HeatQuery{}, qctx);
  j["logmap_s"] = sw.seconds();
  int64_t finite = 0;
  for (size_t i = 0; i < r.u.size(); ++i) finite += std::isfinite(r.u[i]) && std::isfinite(r.v[i]);
  j["logmap_patch"] = r.patch.size();
  j["logmap_finite"] = finite;
  j["logmap_max_distance"] = r.distance.empty() ? 0.0 : *std::max_element(r.distance.begin(), r.distance.end());
  j["rss_end_mb"] = rss_mb();
  j["peak_rss_mb"] = peak_rss_mb();
  j["peak_rss_gib"] = peak_rss_mb() / 1024.0;
  j["within_20_gib"] = peak_rss_mb() <= 20.0 * 1024.0;
  cli::emit(opt, j, [&](std::ostream& os) {
    os << "big: " << in.mesh.num_vertices() << " vertices, nnz(L) " << j["nnz_L"] << ", prepare " << j["prepare_heat_s"]
       << " s, log map " << r.patch.size() << " vertices in " << j["logmap_s"] << " s, peak RSS "
       << j["peak_rss_gib"] << " GiB\n";
  });
  return finite == static_cast<int64_t>(r.patch.size()) && peak_rss_mb() <= 20.0 * 1024.0 ? 0 : 4;
}

// The cancellation latency of long pipelines: cvt on the session, and the
// factorization of the mesh subdivided until it has >= 200k vertices (long
// enough to cancel), each cancelled after delays that reach setup, the first
// iterations and the steady state.
struct CancelLatency {
  Json runs = Json::array();
  double worst = 0;  // ms
  int cancelled_ok = 0;
  int64_t factorize_n = 0;
};

CancelLatency measure_cancel_latency(Session& s, const Mesh& mesh, const Options& bo, uint64_t seed) {
  CancelLatency r;
  // A factorization long enough to cancel: the mesh subdivided until it has >= 200k vertices.
  Mesh big = mesh;
  while (bo.cancel_repeats > 0 && big.num_vertices() < 200000) big = subdivide_midpoint(big, 1);
  const double hb = mean_edge_length(big);
  const CscMatrix A = heat_operator(big, hb * hb);
  auto S = analyze(A, order_matrix(A));
  r.factorize_n = A.ncols;
  for (int rep = 0; rep < bo.cancel_repeats; ++rep) {
    // Different points of each pipeline: setup, first iterations, steady state.
    constexpr double kDelays[] = {10, 60, 250, 800, 2000};
    const double delay = kDelays[rep % 5] * (1 + rep / 5);
    struct Case { const char* name; std::function<void(const RunContext&)> body; };
    const Case cases[] = {
        {"cvt", [&](const RunContext& c2) { s.cvt(std::max(2, s.num_vertices() / 50), 100000, seed + rep, c2); }},
        {"factorize", [&](const RunContext& c2) { (void)factorize(S, A, c2); }},
    };
    for (const Case& cs : cases) {
      std::string why;
      const double ms = cancel_latency(cs.body, delay, why);
      Json e{{"pipeline", cs.name}, {"delay_ms", delay}};
      if (ms >= 0) {
        e["latency_ms"] = ms;
        r.worst = std::max(r.worst, ms);
        ++r.cancelled_ok;
      } else {
        e["not_measured"] = why;
      }
      r.runs.push_back(e);
    }
  }
  return r;
}

int run_stress(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  if (!(bo.seconds > 0)) fail(ErrorCode::BadUsage, "--seconds must be positive");
  if (!(bo.fraction > 0 && bo.fraction <= 1)) fail(ErrorCode::BadUsage, "--fraction must be in (0, 1]");
  if (bo.big) return run_big(opt, bo, ctx);
  const int callers = opt.threads > 0 ? opt.threads : 2;
  Json j;
  j["command"] = "stress";
  const cli::Input in = cli::load_input(opt, ctx);
  j["input"] = cli::input_json(opt, in);
  j["threads"] = callers;
  j["kinds"] = bo.kinds;
  Session s(in.mesh);
  std::vector<Query> qs = make_queries(s, bo, opt.seed);

  // 1. References, one at a time, single-threaded.
  Stopwatch sw;
  {
    RunContext one;
    one.threads = 1;
    one.cancel = ctx.cancel;
    for (Query& q : qs) run_query(s, q, bo.fraction, one, q.answer, q.answer_ids);
  }
  j["reference_s"] = sw.seconds();
  j["queries_per_kind"] = bo.queries_per_kind;
  cli::log("references done (" + std::to_string(qs.size()) + " queries); warm-up");

  Counters c;
  std::atomic<bool> stop{false};
  auto run_callers = [&](bool sweep) {
    std::vector<std::thread> ts;
    for (int t = 0; t < callers; ++t)
      ts.emplace_back([&, t] { caller(s, qs, bo.fraction, t, sweep, stop, ctx, c); });
    return ts;
  };
  // 2. Warm-up: every query once from every caller.
  for (auto& t : run_callers(true)) t.join();
  const double rss_start = rss_mb();
  j["rss_start_mb"] = rss_start;
  cli::log("warm-up done, RSS " + cli::format_number(rss_start) + " MB; " + cli::format_number(bo.seconds) + " s of queries");

  // 3. Timed concurrent run.
  sw.restart();
  const int64_t warm_queries = c.queries.load();
  std::vector<std::thread> ts = run_callers(false);
  Json rss_trace = Json::array();
  double rss_max = rss_start;
  while (sw.seconds() < bo.seconds && !ctx.cancelled()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const double now = rss_mb();
    rss_max = std::max(rss_max, now);
    if (rss_trace.size() < static_cast<size_t>(sw.seconds() / 5.0) + 1) rss_trace.push_back(now);  // one sample per 5 s
  }
  stop.store(true);
  for (auto& t : ts) t.join();
  ctx.check_cancel();
  const double run_s = sw.seconds();
  const double rss_end = rss_mb();

  // 4. Cancellation latency of long pipelines.
  const CancelLatency cl = measure_cancel_latency(s, in.mesh, bo, opt.seed);
  j["cancel_factorize_n"] = cl.factorize_n;
  const double worst = cl.worst;
  const int cancelled_ok = cl.cancelled_ok;

  j["seconds"] = run_s;
  j["queries"] = c.queries.load() - warm_queries;
  j["queries_per_s"] = static_cast<double>(c.queries.load() - warm_queries) / run_s;
  j["warmup_queries"] = warm_queries;
  j["mismatches"] = c.mismatches.load();
  j["errors"] = c.errors.load();
  j["problems"] = c.examples;
  j["rss_end_mb"] = rss_end;
  j["rss_max_mb"] = rss_max;
  j["rss_growth_pct"] = 100.0 * (rss_end - rss_start) / rss_start;
  j["rss_trace_mb"] = rss_trace;
  j["peak_rss_mb"] = peak_rss_mb();
  j["cancel_latency_ms"] = worst;
  j["cancel_measured"] = cancelled_ok;
  j["cancel_runs"] = cl.runs;
  const SessionStats st = s.stats();
  j["session_stats"] = {{"symbolic_analyses", st.symbolic_analyses}, {"numeric_factorizations", st.numeric_factorizations},
                        {"heat_engines", st.heat_engines}, {"deform_operators", st.deform_operators}};
  const bool ok = c.mismatches == 0 && c.errors == 0 && rss_end <= 1.05 * rss_start && worst <= 100.0 &&
                  (cancelled_ok > 0 || bo.cancel_repeats == 0);
  j["pass"] = ok;
  cli::emit(opt, j, [&](std::ostream& os) {
    os << "stress: " << j["queries"] << " queries in " << cli::format_number(run_s) << " s on " << callers
       << " callers, " << j["mismatches"] << " mismatches, " << j["errors"] << " errors; RSS "
       << cli::format_number(rss_start) << " -> " << cli::format_number(rss_end) << " MB; worst cancel latency "
       << cli::format_number(worst) << " ms\n";
  });
  return ok ? 0 : 4;
}

}  // namespace

void register_stress_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add("stress",
                            "Concurrent Session queries checked bit for bit, RSS growth, cancellation latency; "
                            "--big: factor and log map of a large mesh with peak RSS",
                            [bo](const cli::CommonOptions& opt, const RunContext& ctx) { return run_stress(opt, *bo, ctx); });
  app->add_option("--seconds", bo->seconds, "Duration of the concurrent phase (default 60)");
  app->add_option("--fraction", bo->fraction, "Log-map disk, fraction of the vertices (default 0.01)");
  app->add_option("--roi-fraction", bo->roi_fraction, "Deformation region, fraction of the vertices (default 0.02)")
      ->check(CLI::Range(1e-6, 1.0));
  app->add_option("--queries", bo->queries_per_kind, "Distinct queries per kind (default 8)")->check(CLI::Range(1, 1000));
  app->add_option("--cancel-repeats", bo->cancel_repeats, "Cancellations per long pipeline (default 5; 0 = none)")
      ->check(CLI::Range(0, 100));
  app->add_option("--kinds", bo->kinds, "Query kinds in the mix (default geodesic,logmap,heat_values,deform)");
  app->add_flag("--big", bo->big, "Large-mesh mode: load, factor, one log-map query, peak RSS");
}

}  // namespace locus::bench
