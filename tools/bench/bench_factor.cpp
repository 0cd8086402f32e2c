// `locus-bench factor MESH`: locus's numeric core against CHOLMOD (supernodal,
// its default orderings) and Eigen's SimplicialLLT with METIS ordering, on the
// same matrix, in the same run, alternating peer by peer within each repeat so
// that machine noise hits all three alike (DESIGN.md "Measuring").
//
// Phases: analyze (ordering + symbolic), numeric factorization the first time
// (allocates L) and again on the same pattern (refactorization), a 1-lane and
// an 8-lane full solve. Reported: medians over --repeats, nnz(L), ratios
// locus/peer per phase (< 1: locus is faster / sparser), and how far the three
// solutions of the same right-hand side are apart.
//
// Threads: locus and CHOLMOD get the same budget. CHOLMOD parallelises only
// inside BLAS, so OpenBLAS gets --threads N for CHOLMOD's runs; locus runs
// under tbb::global_control (set by the command table) and manages BLAS itself.
// Eigen's simplicial factorization is sequential whatever the budget.
//
// The contenders themselves are in factor_peers.cpp.
#include <oneapi/tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <span>
#include <sstream>
#include <thread>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/order/graph_coarsening.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/bench/factor_peers.hpp"

extern "C" void openblas_set_num_threads(int);
extern "C" int openblas_get_num_threads(void);

namespace locus::bench {
namespace {

using cli::Stopwatch;
using factor::PeerRun;
using factor::Rhs;
using factor::rel_diff;
using factor::run_eigen;
using factor::run_locus;


struct Options {
  cli::OperatorSpec op;
  int repeats = 5;
  std::string cholmod_ordering = "default";  // default (AMD, METIS only if AMD fills badly) | metis | amd
  std::vector<std::string> orderings{"auto", "metis", "amd", "nd", "nd_metis", "nd_geometric"};  // the "orderings" section
  int32_t leaf_size = 0;                      // --leaf-size (0: OrderingOptions' default)
  int coarse_levels = -1;                     // --coarse-levels (-1: OrderingOptions' default)
  bool orderings_only = false;                // skip the peers (ordering experiments)
  std::string threads_list;                   // "1,2,4": the "scaling" section
  std::string scaling_ordering = "auto";      // the ordering of the "scaling" section
};

// The vertex positions of the operator's mesh, for geometric orderings.
struct Positions {
  std::span<const double> x, y, z;
};

OrderingOptions ordering_options(const std::string& name, const Positions& pos, int32_t leaf_size = 0,
                                 int coarse_levels = -1) {
  OrderingOptions o = ordering_by_name(name);
  if (leaf_size > 0) o.leaf_size = leaf_size;
  if (coarse_levels >= 0 && name != "nd_metis") o.coarse_levels = coarse_levels;
  o.x = pos.x;
  o.y = pos.y;
  o.z = pos.z;
  return o;
}


// ------------------------------------------------------------ reporting ----

cli::Json ratios(const cli::Json& mine, const cli::Json& peer) {
  cli::Json r;
  for (const char* k : {"analyze_s", "order_s", "symbolic_s", "factor_first_s", "factor_repeat_s", "solve_s", "solve8_s",
                        "first_answer_s", "nnz_L", "nnz_L_stored"}) {
    if (!mine.contains(k) || !peer.contains(k)) continue;
    const double a = mine[k].get<double>(), b = peer[k].get<double>();
    std::string key(k);
    if (key.size() > 2 && key.compare(key.size() - 2, 2, "_s") == 0) key.resize(key.size() - 2);
    r[key] = b > 0 ? cli::Json(a / b) : cli::Json(nullptr);
  }
  // locus' pipelined first answer against the peer's (sequential) one.
  if (mine.contains("first_answer_beside_s") && peer.contains("first_answer_s") && peer["first_answer_s"] > 0)
    r["first_answer_beside"] = mine["first_answer_beside_s"].get<double>() / peer["first_answer_s"].get<double>();
  return r;
}

void print_table(std::ostream& os, const cli::Json& j) {
  const bool have_cholmod = !j["cholmod"].is_null();
  char line[256];
  std::snprintf(line, sizeof line, "%-18s %12s %12s %12s %14s %12s\n", "phase (median)", "CHOLMOD", "Eigen", "locus",
                "locus/CHOLMOD", "locus/Eigen");
  os << line;
  const std::pair<const char*, const char*> rows[] = {
      {"analyze_s", "analyze [s]"},         {"order_s", "  ordering [s]"}, {"symbolic_s", "  symbolic [s]"},
      {"factor_first_s", "factor [s]"}, {"factor_repeat_s", "refactor [s]"}, {"first_answer_s", "first answer [s]"},
      {"solve_s", "solve 1 lane [s]"},      {"solve8_s", "solve 8 lanes [s]"}, {"nnz_L", "nnz(L) exact"},
      {"nnz_L_stored", "nnz(L) stored"}};
  for (const auto& [key, label] : rows) {
    std::string k(key);
    const std::string rk = k.size() > 2 && k.compare(k.size() - 2, 2, "_s") == 0 ? k.substr(0, k.size() - 2) : k;
    const double c = have_cholmod && j["cholmod"].contains(key) ? j["cholmod"][key].get<double>() : NAN;
    const auto get = [&](const char* peer) {
      return j[peer].contains(key) ? j[peer][key].get<double>() : NAN;
    };
    const double e = get("eigen"), l = get("locus");
    const auto ratio = [&](const char* peer) {
      const cli::Json& r = j[peer];
      return r.is_null() || !r.contains(rk) || r[rk].is_null() ? NAN : r[rk].get<double>();
    };
    std::snprintf(line, sizeof line, "%-18s %12.4g %12.4g %12.4g %14.3f %12.3f\n", label, c, e, l,
                  ratio("ratio_locus_cholmod"), ratio("ratio_locus_eigen"));
    os << line;
  }
  os << "solutions: " << j["agreement"].dump() << "\n";
}

// CHOLMOD at each BLAS thread count of `candidates`, kept: the one with the
// fastest first answer (median) is reported.
struct CholmodRuns {
  std::vector<int> candidates;
  std::vector<PeerRun> runs;
  size_t best() const {
    size_t b = 0;
    for (size_t k = 1; k < runs.size(); ++k)
      if (cli::median(runs[k].first_answer_s) < cli::median(runs[b].first_answer_s)) b = k;
    return b;
  }
};

// The peers on the same matrix, alternating within each repeat.
// locus' first answer as the library gives it on a mesh (prepare_heat_diffusion:
// the ordering and symbolic analysis of the operator's pattern beside the
// assembly of its values, then the factorization) and one solve: wall time from
// the mesh to the solution, the operator included.
double locus_first_answer_beside(const Mesh& mesh, double t, const Rhs& rhs, const RunContext& ctx,
                                 std::vector<double>& x) {
  Stopwatch sw;
  const HeatDiffusion H = prepare_heat_diffusion(mesh, 0.0, t, ctx);
  std::vector<double> work(solve_work_size(H.factor, 1));
  x = rhs.b;
  solve(H.factor, x, work);
  return sw.seconds();
}

void run_peers(const CscMatrix& A, double operator_s, const Positions& pos, const Rhs& rhs, const Options& bo,
               int threads, const RunContext& ctx, cli::Json& j, const Mesh* heat_mesh, double heat_t) {
  const int blas_default = openblas_get_num_threads();
  PeerRun eigen_run, locus_run;
  CholmodRuns chol, chol_metis;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  chol.candidates = {1};
  if (std::min(threads, std::max(cores, 1)) > 1) chol.candidates.push_back(std::min(threads, cores));
  chol_metis.candidates = chol.candidates;
  chol.runs.resize(chol.candidates.size());
  chol_metis.runs.resize(chol.candidates.size());
  const bool extra_metis = bo.cholmod_ordering != "metis";
  std::vector<double> beside_s, x_beside;
  for (int r = 0; r < bo.repeats; ++r) {
#ifdef LOCUS_HAVE_CHOLMOD
    for (size_t k = 0; k < chol.candidates.size(); ++k) {
      openblas_set_num_threads(chol.candidates[k]);
      {
        factor::run_cholmod(bo.cholmod_ordering, A, rhs, chol.runs[k]);
        chol.runs[k].close_repeat(operator_s);
      }
      if (extra_metis) {
        factor::run_cholmod("metis", A, rhs, chol_metis.runs[k]);
        chol_metis.runs[k].close_repeat(operator_s);
      }
      openblas_set_num_threads(blas_default);
      ctx.check_cancel();
    }
#endif
    run_eigen(A, rhs, eigen_run);
    eigen_run.close_repeat(operator_s);
    ctx.check_cancel();
    run_locus(A, ordering_options("auto", pos), rhs, ctx, locus_run);
    locus_run.close_repeat(operator_s);
    ctx.check_cancel();
    if (heat_mesh) beside_s.push_back(locus_first_answer_beside(*heat_mesh, heat_t, rhs, ctx, x_beside));
    ctx.check_cancel();
    cli::log("bench factor: repeat " + std::to_string(r + 1) + "/" + std::to_string(bo.repeats) + " done");
  }
  j["locus"] = locus_run.medians();
  if (heat_mesh) j["locus"]["first_answer_beside_s"] = cli::median(beside_s);
  j["eigen"] = eigen_run.medians();
  j["ratio_locus_eigen"] = ratios(j["locus"], j["eigen"]);
  cli::Json agree{{"locus_vs_eigen", rel_diff(locus_run.x, eigen_run.x)},
                  {"locus_vs_eigen_8", rel_diff(locus_run.x8, eigen_run.x8)},
                  {"residual_locus", cli::relative_residual(A, locus_run.x.data(), rhs.b.data())},
                  {"residual_eigen", cli::relative_residual(A, eigen_run.x.data(), rhs.b.data())}};
  if (heat_mesh) agree["locus_beside_vs_locus"] = rel_diff(x_beside, locus_run.x);
#ifdef LOCUS_HAVE_CHOLMOD
  const PeerRun& cholmod_run = chol.runs[chol.best()];
  j["cholmod"] = cholmod_run.medians();
  j["cholmod"]["ordering_requested"] = bo.cholmod_ordering;
  j["cholmod"]["blas_threads"] = chol.candidates[chol.best()];
  j["cholmod"]["blas_threads_tried"] = chol.candidates;
  j["ratio_locus_cholmod"] = ratios(j["locus"], j["cholmod"]);
  if (extra_metis) {
    j["cholmod_metis"] = chol_metis.runs[chol_metis.best()].medians();
    j["cholmod_metis"]["blas_threads"] = chol_metis.candidates[chol_metis.best()];
    j["ratio_locus_cholmod_metis"] = ratios(j["locus"], j["cholmod_metis"]);
  }
  agree["locus_vs_cholmod"] = rel_diff(locus_run.x, cholmod_run.x);
  agree["locus_vs_cholmod_8"] = rel_diff(locus_run.x8, cholmod_run.x8);
  agree["cholmod_vs_eigen"] = rel_diff(cholmod_run.x, eigen_run.x);
  agree["residual_cholmod"] = cli::relative_residual(A, cholmod_run.x.data(), rhs.b.data());
#else
  (void)threads;
  j["cholmod"] = nullptr;
  j["ratio_locus_cholmod"] = nullptr;
  cli::log("bench factor: built without CHOLMOD (LOCUS_WITH_CHOLMOD_BENCH=OFF); CHOLMOD column empty");
#endif
  j["agreement"] = agree;
}

Rhs make_rhs(int32_t n, uint64_t seed) {
  Rhs rhs;
  rhs.n = n;
  const size_t un = static_cast<size_t>(n);
  rhs.b = cli::random_vector(un, seed);
  rhs.b8.resize(un * kLanes);
  std::copy(rhs.b.begin(), rhs.b.end(), rhs.b8.begin());
  for (int l = 1; l < kLanes; ++l) {
    const std::vector<double> col = cli::random_vector(un, seed + l);
    std::copy(col.begin(), col.end(), rhs.b8.begin() + static_cast<std::ptrdiff_t>(l * un));
  }
  return rhs;
}

// The "orderings" section: analysis alone per ordering (medians), with the
// fill and etree heights each gives.
cli::Json run_orderings(const CscMatrix& A, const Positions& pos, const Options& bo, const RunContext& ctx) {
  cli::Json out = cli::Json::object();
  const size_t k = bo.orderings.size();
  std::vector<std::vector<double>> order_s(k), order_cpu_s(k), symbolic_s(k);
  std::vector<std::shared_ptr<const SymbolicFactor>> sym(k);
  // Repeats outside, orderings inside: on a shared machine every ordering
  // sees the same load drift. order_cpu_s is the process' CPU time of the
  // ordering (all threads): the work, whatever the load took away.
  const auto cpu_now = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  for (int r = 0; r < bo.repeats; ++r)
    for (size_t i = 0; i < k; ++i) {
      const OrderingOptions oo = ordering_options(bo.orderings[i], pos, bo.leaf_size, bo.coarse_levels);
      const double cpu0 = cpu_now();
      Stopwatch sw;
      const Ordering ord = order_matrix(A, oo, ctx);
      order_s[i].push_back(sw.seconds());
      order_cpu_s[i].push_back(cpu_now() - cpu0);
      sw.restart();
      sym[i] = analyze(A, ord, {}, ctx);
      symbolic_s[i].push_back(sw.seconds());
      ctx.check_cancel();
    }
  // The shared coarsening alone (graph_coarsening.hpp), timed apart: it runs
  // before the dissection's task tree, on its critical path.
  std::vector<double> coarsen_s, coarsen_cpu_s;
  int32_t coarse_n = 0;
  const OrderingOptions nd = ordering_options("nd", pos, bo.leaf_size, bo.coarse_levels);
  if (std::find(bo.orderings.begin(), bo.orderings.end(), "nd") != bo.orderings.end() && nd.coarse_levels > 0) {
    const AdjacencyGraph g = adjacency_of(A);
    HostVector<int32_t> cmap;
    for (int r = 0; r < bo.repeats; ++r) {
      const double cpu0 = cpu_now();
      Stopwatch sw;
      coarse_n = coarsening_map(g, nd.coarse_levels, cmap);
      coarsen_s.push_back(sw.seconds());
      coarsen_cpu_s.push_back(cpu_now() - cpu0);
    }
  }
  for (size_t i = 0; i < k; ++i) {
    const std::string& name = bo.orderings[i];
    out[name] = {{"order_s", cli::median(order_s[i])},
                 {"order_cpu_s", cli::median(order_cpu_s[i])},
                 {"symbolic_s", cli::median(symbolic_s[i])},
                 {"nnz_L", sym[i]->nnz_exact},
                 {"nnz_L_stored", sym[i]->nnz_L},
                 {"etree_height", sym[i]->etree_height},
                 {"super_etree_height", sym[i]->super_etree_height},
                 {"supernodes", sym[i]->ns},
                 {"flops", static_cast<double>(sym[i]->flops())}};
    if (name == "nd" && !coarsen_s.empty()) {
      out[name]["coarsen_s"] = cli::median(coarsen_s);
      out[name]["coarsen_cpu_s"] = cli::median(coarsen_cpu_s);
      out[name]["coarse_levels"] = nd.coarse_levels;
      out[name]["coarse_vertices"] = coarse_n;
    }
    cli::log("bench factor: ordering " + name + " " + out[name].dump());
  }
  return out;
}

// The "scaling" section: every phase of locus (ctx.threads = T) and of
// CHOLMOD (T BLAS threads) for each T of --threads-list, medians.
cli::Json run_scaling(const CscMatrix& A, double operator_s, const Positions& pos, const Rhs& rhs,
                      const Options& bo, const RunContext& ctx) {
  std::vector<int> list;
  std::stringstream ss(bo.threads_list);
  for (std::string item; std::getline(ss, item, ',');) {
    const int t = std::stoi(item);
    if (t < 1) fail(ErrorCode::BadUsage, "--threads-list: thread counts must be >= 1");
    list.push_back(t);
  }
  cli::Json rows = cli::Json::array();
  const int blas_default = openblas_get_num_threads();
  for (const int t : list) {
    RunContext c = ctx;
    c.threads = t;
    PeerRun lr, cr;
    for (int r = 0; r < bo.repeats; ++r) {
      run_locus(A, ordering_options(bo.scaling_ordering, pos), rhs, c, lr);
      lr.close_repeat(operator_s);
#ifdef LOCUS_HAVE_CHOLMOD
      openblas_set_num_threads(t);
      {
        factor::run_cholmod("default", A, rhs, cr);
      }
      cr.close_repeat(operator_s);
      openblas_set_num_threads(blas_default);
#endif
      ctx.check_cancel();
    }
    cli::Json row{{"threads", t}, {"locus", lr.medians()}};
    row["locus"]["ordering"] = bo.scaling_ordering;
#ifdef LOCUS_HAVE_CHOLMOD
    row["cholmod"] = cr.medians();
#endif
    cli::log("bench factor: scaling " + row.dump());
    rows.push_back(row);
  }
  return rows;
}

int run_bench_factor(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  cli::validate_operator_spec(bo.op);
  cli::Input in = cli::load_input(opt, ctx);
  Stopwatch op_sw;
  const cli::BuiltOperator op = cli::build_operator(in.mesh, bo.op);
  const double operator_first_s = op_sw.seconds();
  // Every other phase is a median of warm repeats; so is the operator's time
  // (the first build also pays for first-touch page faults).
  std::vector<double> op_samples;
  for (int r = 0; r < bo.repeats; ++r) {
    op_sw.restart();
    (void)cli::build_operator(in.mesh, bo.op);
    op_samples.push_back(op_sw.seconds());
  }
  const double operator_s = cli::median(op_samples);
  const CscMatrix& A = op.A;
  const Rhs rhs = make_rhs(A.ncols, opt.seed);
  Positions pos;
  if (in.mesh.num_vertices() == A.ncols) pos = {in.mesh.x, in.mesh.y, in.mesh.z};

  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  cli::Json j{{"command", "bench factor"}, {"input", cli::input_json(opt, in)}};
  j["operator"] = bo.op.kind;
  j["t"] = op.t;
  j["h"] = op.h;
  j["n"] = rhs.n;
  j["nnz_A"] = A.nnz();
  j["threads"] = threads;
  j["repeats"] = bo.repeats;
  j["seed"] = opt.seed;
  j["operator_s"] = operator_s;
  j["operator_first_s"] = operator_first_s;
  for (const std::string& name : bo.orderings) ordering_options(name, pos);  // bad names fail before the long runs
  // The pipelined first answer needs the mesh's own heat operator (not --operator laplacian).
  const Mesh* heat_mesh = bo.op.kind == "heat" && in.mesh.num_vertices() == A.ncols ? &in.mesh : nullptr;
  if (!bo.orderings_only) run_peers(A, operator_s, pos, rhs, bo, threads, ctx, j, heat_mesh, op.t);
  j["orderings"] = run_orderings(A, pos, bo, ctx);
  if (!bo.threads_list.empty()) j["scaling"] = run_scaling(A, operator_s, pos, rhs, bo, ctx);
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};

  // The table always goes to stderr; stdout carries the JSON object only.
  std::ostringstream table;
  table << opt.mesh_path << ": n " << rhs.n << ", nnz(A) " << A.nnz() << ", " << bo.op.kind << " operator, threads "
        << threads << ", " << bo.repeats << " repeats\n";
  if (!bo.orderings_only) print_table(table, j);
  for (const auto& [name, o] : j["orderings"].items())
    table << "ordering " << name << ": " << o.dump() << "\n";
  std::cerr << table.str();
  if (opt.json) cli::emit(opt, j, {});
  return 0;
}

}  // namespace

OrderingOptions ordering_by_name(const std::string& name) {
  using M = OrderingOptions::Method;
  OrderingOptions o;
  if (name == "metis") o.method = M::Metis;
  else if (name == "amd") o.method = M::Amd;
  else if (name == "nd") o.method = M::NestedDissection;
  else if (name == "nd_geometric") { o.method = M::NestedDissection; o.separator = OrderingOptions::Separator::Geometric; }
  else if (name == "nd_nohalo") { o.method = M::NestedDissection; o.halo = false; }
  else if (name == "nd_metis") { o.method = M::NestedDissection; o.coarse_levels = 0; }  // METIS on every node's graph
  else if (name != "auto") fail(ErrorCode::BadUsage, "unknown ordering '" + name + "'");
  return o;
}

void register_factor_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add("factor", "Factor and solve with locus, CHOLMOD and Eigen (METIS); medians and ratios",
                            [bo](const cli::CommonOptions& opt, const RunContext& ctx) {
                              return run_bench_factor(opt, *bo, ctx);
                            });
  cli::add_operator_options(app, bo->op);
  app->add_option("--repeats,--repeat", bo->repeats, "Repeats; medians are reported (default 5)")
      ->check(CLI::Range(1, 1000));
  app->add_option("--orderings", bo->orderings,
                  "Orderings analysed in the \"orderings\" section: auto metis amd nd nd_metis nd_geometric nd_nohalo "
                  "(default: all but nd_nohalo)")
      ->delimiter(',');
  app->add_option("--leaf-size", bo->leaf_size, "Nested dissection leaf size in the \"orderings\" section");
  app->add_option("--coarse-levels", bo->coarse_levels,
                  "Nested dissection: rounds of matching of the shared coarsening in the \"orderings\" section "
                  "(default: OrderingOptions')")
      ->check(CLI::Range(0, 30));
  app->add_flag("--orderings-only", bo->orderings_only, "Only the \"orderings\" section (no peers)");
  app->add_option("--threads-list", bo->threads_list,
                  "Comma-separated thread counts (1,2,4,8,16): every phase of locus and CHOLMOD at each, "
                  "in the \"scaling\" section");
  app->add_option("--scaling-ordering", bo->scaling_ordering,
                  "locus' ordering in the \"scaling\" section (names as --orderings; default auto)");
  app->add_option("--cholmod-ordering", bo->cholmod_ordering,
                  "CHOLMOD's ordering: default (its own choice), metis or amd (default: default)")
      ->check(CLI::IsMember({"default", "metis", "amd"}));
}

}  // namespace locus::bench
