// `locus-bench submesh MESH`: the factor-once update (thesis §5.7, Figures
// 5.6–5.9) against refactoring the submatrix A_II from scratch.
//
// The global operator is factored once and indexed for updates once
// (FactorUpdater's set-up; both reported, not part of the per-patch times). For every cell (a patch
// size as a fraction of the vertices) and every random BFS patch I (seeded):
//   (a) update:           locus FactorUpdater::update(I), sharing form (L held by shared pointer):
//                         unchanged whole blocks borrowed from L, the others recomputed or copied;
//                         A_II not extracted (FactorUpdateOptions::submatrix = false): like (b)-(d),
//                         which are handed A_II, it is not charged for that
//   (a') update_copying:  the copying form with A_II extracted (the former headline)
//   (b) locus refactor:   locus analyze(A_II, restricted order) + factorize
//   (c) CHOLMOD given:    cholmod_analyze_p with that order (CHOLMOD_GIVEN, no postorder) + factorize
//   (d) CHOLMOD METIS:    cholmod_analyze with METIS (its own ordering of A_II) + factorize
// A_II is extracted once per patch outside the timers, as in the thesis. The
// contenders run back to back on the same patch, their order rotating from
// patch to patch so that machine noise hits all alike. Every update is
// checked (relative residual of A_II x = b) before it is counted.
// --sets scattered draws uniformly random vertices instead of BFS patches (the
// edge case of thesis Fig. 5.11, where the update must not lose to (b)).
// JSON: `cells` with medians and ratios; the spread of the speedups goes to stderr.
// Page faults on fresh memory cost 6x more on some VMs than on others and hit
// the contenders that allocate most: each one's minor faults are reported, and
// --warm-heap takes them out of the comparison (freed pages are kept and reused).
// CHOLMOD's row deletion (cholmod_rowdel per vertex of B, the thesis's
// "low-rank update" peer) is measured only with --updown, for the smallest
// fraction, capped at --updown-cap seconds per patch (reported as a lower
// bound when the cap is hit).
#include <oneapi/tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include <malloc.h>
#include <sys/resource.h>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "tools/bench/bench_commands.hpp"

#ifdef LOCUS_HAVE_CHOLMOD
#include <cholmod.h>
#endif

extern "C" void openblas_set_num_threads(int);
extern "C" int openblas_get_num_threads(void);

namespace locus::bench {
namespace {

using cli::Stopwatch;

// Minor page faults of the whole process so far: around an update they count
// the first touches of fresh memory (~0.45 ms per MB on one thread).
long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

struct Options {
  std::string fractions = "0.1,0.25,0.5";
  int patches = 5;
  std::string op = "laplacian";
  bool updown = false;
  double updown_cap = 60.0;
  bool warm_heap = false;
  std::string sets = "bfs";
};

std::vector<double> parse_fractions(const std::string& text) {
  std::vector<double> f;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !(v > 0 && v < 1))
      fail(ErrorCode::BadUsage, "--fractions expects numbers in (0, 1) separated by commas, got '" + text + "'");
    f.push_back(v);
  }
  if (f.empty()) fail(ErrorCode::BadUsage, "--fractions is empty");
  return f;
}

// min, lower quartile, median, upper quartile, max.
std::array<double, 5> spread(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto q = [&](double p) {
    const double k = p * static_cast<double>(v.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(k)), hi = static_cast<size_t>(std::ceil(k));
    return v[lo] + (k - static_cast<double>(lo)) * (v[hi] - v[lo]);
  };
  return {v.front(), q(0.25), q(0.5), q(0.75), v.back()};
}

#ifdef LOCUS_HAVE_CHOLMOD
class Cholmod {
 public:
  Cholmod() { cholmod_start(&c_); }
  ~Cholmod() { cholmod_finish(&c_); }
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;

  // Analyze + factorize A (lower) with `perm` (given order, no postorder) or
  // with METIS when perm is empty; returns seconds. The factor is freed.
  // analyze_s and flops (CHOLMOD's own count, Common->fl) of the last call are kept.
  double analyze_s = 0, flops = 0;
  double analyze_factorize(const CscMatrix& A, const std::vector<int32_t>& perm) {
    cholmod_sparse* As = to_cholmod(A);
    c_.supernodal = CHOLMOD_SUPERNODAL;
    c_.nmethods = 1;
    c_.postorder = perm.empty() ? 1 : 0;
    c_.method[0].ordering = perm.empty() ? CHOLMOD_METIS : CHOLMOD_GIVEN;
    std::vector<int> p(perm.begin(), perm.end());
    Stopwatch sw;
    cholmod_factor* L = perm.empty() ? cholmod_analyze(As, &c_) : cholmod_analyze_p(As, p.data(), nullptr, 0, &c_);
    check("cholmod_analyze");
    analyze_s = sw.seconds();
    flops = c_.fl;
    cholmod_factorize(As, L, &c_);
    const double t = sw.seconds();
    const int status = c_.status;
    cholmod_free_factor(&L, &c_);
    cholmod_free_sparse(&As, &c_);
    if (status != CHOLMOD_OK) fail(ErrorCode::Numerical, "CHOLMOD factorize failed with status " + std::to_string(status));
    return t;
  }

  // Factor of A (METIS), then cholmod_rowdel for every index outside `keep`,
  // leaving the factor of A_II (padded with identity rows). Seconds of the
  // deletions only; stops after `cap` seconds (then returns a lower bound and sets capped).
  double rowdel(const CscMatrix& A, const std::vector<int32_t>& keep_sorted, double cap, bool& capped) {
    cholmod_sparse* As = to_cholmod(A);
    c_.supernodal = CHOLMOD_SUPERNODAL;
    c_.nmethods = 1;
    c_.postorder = 1;
    c_.method[0].ordering = CHOLMOD_METIS;
    cholmod_factor* L = cholmod_analyze(As, &c_);
    cholmod_factorize(As, L, &c_);
    check("cholmod_factorize");
    std::vector<uint8_t> keep(static_cast<size_t>(A.ncols), 0);
    for (int32_t v : keep_sorted) keep[v] = 1;
    capped = false;
    Stopwatch sw;
    // cholmod_rowdel works on a simplicial LDL' factor; the conversion is part of the cost.
    cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, L, &c_);
    // Rows of the factor are in CHOLMOD's permuted numbering: row k is vertex Perm[k].
    const int* perm = static_cast<const int*>(L->Perm);
    for (int32_t k = 0; k < A.ncols; ++k) {
      if (keep[perm[k]]) continue;
      cholmod_rowdel(static_cast<size_t>(k), nullptr, L, &c_);
      if (sw.seconds() > cap) {
        capped = true;
        break;
      }
    }
    const double t = sw.seconds();
    cholmod_free_factor(&L, &c_);
    cholmod_free_sparse(&As, &c_);
    return t;
  }

 private:
  cholmod_sparse* to_cholmod(const CscMatrix& A) {
    const size_t n = static_cast<size_t>(A.ncols);
    if (A.nnz() > std::numeric_limits<int>::max()) fail(ErrorCode::ResourceLimit, "CHOLMOD peer: nnz exceeds 32-bit indices");
    cholmod_sparse* S = cholmod_allocate_sparse(n, n, static_cast<size_t>(A.nnz()), 1, 1, -1, CHOLMOD_REAL, &c_);
    check("cholmod_allocate_sparse");
    int* p = static_cast<int*>(S->p);
    for (size_t k = 0; k <= n; ++k) p[k] = static_cast<int>(A.colptr[k]);
    std::copy(A.rowind.begin(), A.rowind.end(), static_cast<int*>(S->i));
    std::copy(A.values.begin(), A.values.end(), static_cast<double*>(S->x));
    return S;
  }
  void check(const char* what) {
    if (c_.status == CHOLMOD_NOT_POSDEF) fail(ErrorCode::Numerical, std::string("CHOLMOD: not positive definite (") + what + ")");
    if (c_.status != CHOLMOD_OK) fail(ErrorCode::Internal, std::string(what) + " failed with status " + std::to_string(c_.status));
  }
  cholmod_common c_{};
};
#endif

struct Cell {
  double fraction = 0;
  std::vector<double> copying_s, mem_owned, sp_given_copying;
  std::vector<double> update_s, refactor_s, given_s, metis_s, cols, mem, sp_given, sp_refactor, sp_metis, residual;
  std::vector<double> zeros;  // 1 - nnz(exact factor of A_II) / nnz(restricted structure)
  // Extraction of A_II from A (principal_submatrix, timed apart: (b)-(d) are
  // handed A_II), (b) + that over the update, and the update's refactored sets
  // and touched shares (FactorUpdateStats: a scattered set is factored afresh).
  std::vector<double> extract_s, sp_refactor_extract, refactored, touched_share;
  std::vector<double> structure_s, assemble_s, mark_s, copy_s, factor_s;  // phases of the update
  // Minor page faults during the timed update, (b) and (c): first touches of
  // fresh memory, whose cost depends on the machine (0.45 ms per MB on one VM,
  // 2.7 on another), so they are reported beside the times.
  std::vector<double> update_faults, refactor_faults, given_faults;
  // Flops (SymbolicFactor::flops' count: what each column sends to the rows
  // below it) of the update's recomputed supernodes and of (b)'s whole
  // factorization; CHOLMOD's own count (same formula) and analyze time for (c).
  std::vector<double> flops_recomputed, flops_refactor, cholmod_flops, given_analyze_s;
  std::vector<double> rowdel_s;
  int rowdel_capped = 0;
};

// The set I of one patch: a BFS patch around `seed`, or (scattered) uniformly
// random vertices (thesis Fig. 5.11's extreme).
std::vector<int32_t> patch_set(const Adjacency& adj, int32_t n, int32_t seed, int32_t count, const std::string& sets) {
  std::vector<int32_t> I;
  if (sets == "bfs") {
    I = grow_ring_vertices(adj, seed, count);
  } else {
    std::vector<uint8_t> in(static_cast<size_t>(n), 0);
    std::mt19937_64 pick(static_cast<uint64_t>(seed));
    while (static_cast<int32_t>(I.size()) < count) {
      const int32_t v = static_cast<int32_t>(pick() % static_cast<uint64_t>(n));
      if (!in[v]) {
        in[v] = 1;
        I.push_back(v);
      }
    }
  }
  return I;
}

// One patch's measurements: the contenders' times, faults and sizes, the
// timed update and (b)'s factor (the residual yardstick for the update).
struct PatchTimes {
  double t_update = 0, t_copying = 0, t_refactor = 0, t_given = NAN, t_metis = NAN;
  long faults_update = 0, faults_refactor = 0, faults_given = 0;
  int64_t values_refactor = 0, nnz_exact = 0, flops_refactor = 0;
  double given_analyze = NAN, given_flops = NAN;
  FactorUpdate up;
  NumericFactor scratch;
};

// The global operator, its factor, the two updaters and the peers: what every patch is measured against.
struct SubmeshRun {
  const cli::CommonOptions& opt;
  const Options& bo;
  const RunContext& ctx;
  const CscMatrix& A;
  FactorUpdater& updater;  // (a): sharing form, A_II not extracted
  FactorUpdater& copying;  // (a') and A_II for the other contenders
  const int threads, blas_default;
#ifdef LOCUS_HAVE_CHOLMOD
  Cholmod ch{};
#endif

  PatchTimes time_contenders(const std::vector<int32_t>& I, const FactorUpdate& ref, int rotation);
  void record(Cell& cell, const PatchTimes& pt, const FactorUpdate& ref, int p);
};

// The contenders back to back on one patch, their order rotated by `rotation`.
PatchTimes SubmeshRun::time_contenders(const std::vector<int32_t>& I, const FactorUpdate& ref, int rotation) {
  const CscMatrix& Aii = ref.A_sub;
  const std::vector<int32_t> order(ref.factor.symbolic->perm);
  PatchTimes pt;
  Stopwatch sw;
  for (int k = 0; k < 5; ++k) {
    switch ((k + rotation) % 5) {
      case 0: {
        const long f0 = minor_faults();
        sw.restart();
        pt.up = updater.update(I, ctx);
        pt.t_update = sw.seconds();
        pt.faults_update = minor_faults() - f0;
        break;
      }
      case 4: {
        sw.restart();
        const FactorUpdate u = copying.update(I, ctx);
        pt.t_copying = sw.seconds();
        break;
      }
      case 1: {
        const long f0 = minor_faults();
        sw.restart();
        auto S = analyze(Aii, Ordering{order, std::vector<int32_t>(ref.factor.symbolic->iperm)});
        pt.scratch = factorize(S, Aii, ctx);
        pt.t_refactor = sw.seconds();
        pt.faults_refactor = minor_faults() - f0;
        pt.values_refactor = static_cast<int64_t>(pt.scratch.values.size());
        pt.nnz_exact = S->nnz_exact;
        pt.flops_refactor = S->flops();
        break;
      }
#ifdef LOCUS_HAVE_CHOLMOD
      case 2: {
        openblas_set_num_threads(threads);
        const long f0 = minor_faults();
        pt.t_given = ch.analyze_factorize(Aii, order);
        pt.faults_given = minor_faults() - f0;
        pt.given_analyze = ch.analyze_s;
        pt.given_flops = ch.flops;
        openblas_set_num_threads(blas_default);
        break;
      }
      case 3:
        openblas_set_num_threads(threads);
        pt.t_metis = ch.analyze_factorize(Aii, {});
        openblas_set_num_threads(blas_default);
        break;
#endif
      default: break;
    }
  }
  return pt;
}

// Checks the timed update (it must solve A_II) and adds the patch to its cell.
void SubmeshRun::record(Cell& cell, const PatchTimes& pt, const FactorUpdate& ref, int p) {
  const CscMatrix& Aii = ref.A_sub;
  const FactorUpdate& up = pt.up;
  // Correctness before speed: the timed update must solve A_II.
  const std::vector<double> b = cli::random_vector(static_cast<size_t>(Aii.ncols), opt.seed + static_cast<uint64_t>(p));
  std::vector<double> x = b, xs = b;
  solve(up.factor, x);
  solve(pt.scratch, xs);
  const double res = cli::relative_residual(Aii, x.data(), b.data());
  const double res_scratch = cli::relative_residual(Aii, xs.data(), b.data());
  // The bi-Laplacian's condition number is the Laplacian's squared: a fixed
  // bound would fail good factors, so the update must match a from-scratch
  // factor of the same matrix (within 100x) or reach 1e-8.
  if (!(res <= std::max(1e-8, 100.0 * res_scratch)))
    fail(ErrorCode::Internal, "bench submesh: updated factor gives relative residual " + cli::format_number(res) +
                                  " (from-scratch factor: " + cli::format_number(res_scratch) + ")");
  cell.residual.push_back(res);
  cell.update_s.push_back(pt.t_update);
  cell.copying_s.push_back(pt.t_copying);
  cell.mem_owned.push_back(static_cast<double>(up.stats.values_stored - up.stats.values_borrowed) /
                           static_cast<double>(pt.values_refactor));
  cell.refactor_s.push_back(pt.t_refactor);
  cell.cols.push_back(up.stats.columns_updated_fraction);
  cell.mem.push_back(static_cast<double>(up.stats.values_stored) / static_cast<double>(pt.values_refactor));
  cell.sp_refactor.push_back(pt.t_refactor / pt.t_update);
  {
    Stopwatch sw;
    const CscMatrix E = principal_submatrix(A, ref.vertices);
    const double t_extract = sw.seconds();
    if (E.nnz() != Aii.nnz()) fail(ErrorCode::Internal, "bench submesh: principal_submatrix differs from the update's A_II");
    cell.extract_s.push_back(t_extract);
    cell.sp_refactor_extract.push_back((pt.t_refactor + t_extract) / pt.t_update);
    cell.refactored.push_back(up.stats.refactored ? 1.0 : 0.0);
    cell.touched_share.push_back(up.stats.touched_share);
  }
  cell.structure_s.push_back(up.stats.structure_s);
  cell.assemble_s.push_back(up.stats.assemble_s);
  cell.mark_s.push_back(up.stats.mark_s);
  cell.copy_s.push_back(up.stats.copy_s);
  cell.factor_s.push_back(up.stats.factor_s);
  cell.update_faults.push_back(static_cast<double>(pt.faults_update));
  cell.refactor_faults.push_back(static_cast<double>(pt.faults_refactor));
  if (!std::isnan(pt.t_given)) cell.given_faults.push_back(static_cast<double>(pt.faults_given));
  cell.flops_recomputed.push_back(static_cast<double>(up.stats.flops_recomputed));
  cell.flops_refactor.push_back(static_cast<double>(pt.flops_refactor));
  if (!std::isnan(pt.given_flops)) {
    cell.cholmod_flops.push_back(pt.given_flops);
    cell.given_analyze_s.push_back(pt.given_analyze);
  }
  cell.zeros.push_back(1.0 - static_cast<double>(pt.nnz_exact) / static_cast<double>(up.stats.nnz_stored));
  if (!std::isnan(pt.t_given)) {
    cell.given_s.push_back(pt.t_given);
    cell.metis_s.push_back(pt.t_metis);
    cell.sp_given.push_back(pt.t_given / pt.t_update);
    cell.sp_given_copying.push_back(pt.t_given / pt.t_copying);
    cell.sp_metis.push_back(pt.t_metis / pt.t_update);
  }
}

cli::Json med(const std::vector<double>& v) { return v.empty() ? cli::Json(nullptr) : cli::Json(cli::median(v)); }

// The JSON of one cell: medians and ratios.
cli::Json cell_json(const Cell& c) {
  cli::Json e{{"fraction", c.fraction}, {"patches", c.update_s.size()}};
  e["update_s"] = med(c.update_s);
  e["locus_refactor_s"] = med(c.refactor_s);
  e["cholmod_given_s"] = med(c.given_s);
  e["cholmod_metis_s"] = med(c.metis_s);
  e["speedup_vs_cholmod_given"] = med(c.sp_given);
  e["speedup_vs_cholmod_metis"] = med(c.sp_metis);
  e["speedup_vs_locus_refactor"] = med(c.sp_refactor);
  e["extract_s"] = med(c.extract_s);
  e["speedup_vs_locus_refactor_with_extract"] = med(c.sp_refactor_extract);
  e["min_speedup_vs_locus_refactor"] = *std::min_element(c.sp_refactor.begin(), c.sp_refactor.end());
  e["refactored_sets"] = std::count(c.refactored.begin(), c.refactored.end(), 1.0);
  e["touched_share"] = med(c.touched_share);
  e["columns_updated_fraction"] = med(c.cols);
  e["memory_ratio"] = med(c.mem);  // values the factor holds (own and borrowed) / (b)'s
  e["memory_owned_ratio"] = med(c.mem_owned);  // values it stores itself / (b)'s
  e["update_copying_s"] = med(c.copying_s);
  e["speedup_copying_vs_cholmod_given"] = med(c.sp_given_copying);
  // Entries the restricted structure stores beyond the exact factor of A_II
  // (explicit zeros: fill of L not present in L', plus L's amalgamation zeros).
  e["explicit_zero_fraction"] = med(c.zeros);
  e["update_phases"] = {{"structure_s", med(c.structure_s)}, {"assemble_s", med(c.assemble_s)}, {"mark_s", med(c.mark_s)},
                        {"copy_s", med(c.copy_s)}, {"factor_s", med(c.factor_s)}};
  e["update_minor_faults"] = med(c.update_faults);
  e["locus_refactor_minor_faults"] = med(c.refactor_faults);
  e["cholmod_given_minor_faults"] = med(c.given_faults);
  e["flops_recomputed"] = med(c.flops_recomputed);
  e["flops_refactor"] = med(c.flops_refactor);
  e["cholmod_given_flops"] = med(c.cholmod_flops);
  e["cholmod_given_analyze_s"] = med(c.given_analyze_s);
  e["max_residual"] = *std::max_element(c.residual.begin(), c.residual.end());
  if (!c.rowdel_s.empty()) {
    e["cholmod_rowdel_s"] = med(c.rowdel_s);
    e["cholmod_rowdel_capped"] = c.rowdel_capped;
  }
  return e;
}

// The human-readable table (stderr): medians per cell, then the spread of the speedups.
std::string cell_table(const cli::CommonOptions& opt, const Options& bo, int32_t n, int threads,
                       const std::vector<Cell>& cells, const cli::Json& jc) {
  std::ostringstream table;
  table << opt.mesh_path << ": n " << n << ", " << bo.op << ", " << bo.patches << " patches per cell, threads "
        << threads << "\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-8s %10s %10s %10s %10s %9s %9s %9s %7s\n", "fraction", "update", "locus_ref",
                "chol_given", "chol_metis", "x_given", "x_locref", "cols_upd", "mem");
  table << line;
  for (size_t k = 0; k < cells.size(); ++k) {
    const Cell& c = cells[k];
    const cli::Json& e = jc[k];
    auto num = [](const cli::Json& v) { return v.is_null() ? NAN : v.get<double>(); };
    std::snprintf(line, sizeof line, "%-8.3g %10.4g %10.4g %10.4g %10.4g %9.2f %9.2f %9.3f %7.3f\n", c.fraction,
                  num(e["update_s"]), num(e["locus_refactor_s"]), num(e["cholmod_given_s"]), num(e["cholmod_metis_s"]),
                  num(e["speedup_vs_cholmod_given"]), num(e["speedup_vs_locus_refactor"]),
                  num(e["columns_updated_fraction"]), num(e["memory_ratio"]));
    table << line;
  }
  table << "speedup spread (min, q1, median, q3, max):\n";
  for (const Cell& c : cells) {
    for (const auto& [name, v] : {std::pair<const char*, const std::vector<double>*>{"vs CHOLMOD given", &c.sp_given},
                                  {"vs CHOLMOD METIS", &c.sp_metis},
                                  {"vs locus refactor", &c.sp_refactor}}) {
      if (v->empty()) continue;
      const auto s = spread(*v);
      std::snprintf(line, sizeof line, "  %-6.3g %-18s %7.2f %7.2f %7.2f %7.2f %7.2f\n", c.fraction, name, s[0], s[1],
                    s[2], s[3], s[4]);
      table << line;
    }
    if (!c.rowdel_s.empty())
      table << "  " << c.fraction << " CHOLMOD rowdel median " << cli::median(c.rowdel_s) << " s"
            << (c.rowdel_capped ? " (capped: lower bound)" : "") << "\n";
  }
  return table.str();
}

int run_bench_submesh(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  const std::vector<double> fractions = parse_fractions(bo.fractions);
  if (bo.op != "laplacian" && bo.op != "bilaplacian")
    fail(ErrorCode::BadUsage, "--operator must be laplacian or bilaplacian, got '" + bo.op + "'");
  if (bo.warm_heap) {
    // Every allocation from the heap, which keeps freed pages: after the first
    // patches no contender pays first-touch faults (mallopt returns 1 on success).
    if (mallopt(M_MMAP_MAX, 0) != 1 || mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max()) != 1)
      fail(ErrorCode::Internal, "bench submesh: --warm-heap: mallopt refused the settings");
  }
  cli::Input in = cli::load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  Stopwatch sw;
  // laplacian: -L_C + eps M; bilaplacian: K M^{-1} K with K = -L_C + eps M (A^T M^{-1} A).
  const CscMatrix A = bo.op == "laplacian" ? (check_requirements(mesh, MeshRequirements{}), regularized_laplacian(mesh))
                                           : deform_matrices(mesh, DeformEnergy::Bilaplacian).A;
  const double operator_s = sw.seconds();
  const int32_t n = A.ncols;
  sw.restart();
  const auto Lp = std::make_shared<const NumericFactor>(factorize(analyze(A, order_matrix(A)), A, ctx));
  const NumericFactor& L = *Lp;
  const double global_s = sw.seconds();
  // The updater indexes L once (pattern check, row -> supernode lists): part of the set-up, like the factor.
  sw.restart();
  FactorUpdateOptions factor_only;
  factor_only.submatrix = false;
  FactorUpdater updater(Lp, A, factor_only);
  const double updater_s = sw.seconds();
  FactorUpdater copying(L, A);
  const Adjacency adj = vertex_adjacency(mesh);
  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  const int blas_default = openblas_get_num_threads();
  cli::log("bench submesh: n " + std::to_string(n) + ", nnz(L) " + std::to_string(L.symbolic->nnz_L) +
           ", global factor " + cli::format_number(global_s) + " s, updater set-up " +
           cli::format_number(updater_s) + " s");

  std::mt19937_64 rng(opt.seed);
  std::vector<Cell> cells;
  SubmeshRun run{opt, bo, ctx, A, updater, copying, threads, blas_default};
  int rotation = 0;
  for (double frac : fractions) {
    Cell cell;
    cell.fraction = frac;
    const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(frac * n)));
    for (int p = 0; p < bo.patches; ++p) {
      ctx.check_cancel();
      const int32_t seed = static_cast<int32_t>(rng() % static_cast<uint64_t>(n));
      const std::vector<int32_t> I = patch_set(adj, n, seed, count, bo.sets);
      // A_II and the restricted order, outside the timers (one untimed update provides both).
      const FactorUpdate ref = copying.update(I, ctx);
      const PatchTimes pt = run.time_contenders(I, ref, rotation);
      ++rotation;
      run.record(cell, pt, ref, p);
#ifdef LOCUS_HAVE_CHOLMOD
      if (bo.updown && frac == *std::min_element(fractions.begin(), fractions.end())) {
        bool capped = false;
        cell.rowdel_s.push_back(run.ch.rowdel(A, ref.vertices, bo.updown_cap, capped));
        cell.rowdel_capped += capped;
      }
#endif
      cli::log("bench submesh: fraction " + cli::format_number(frac) + " patch " + std::to_string(p + 1) + "/" +
               std::to_string(bo.patches) + ": update " + cli::format_number(pt.t_update) + " s, locus refactor " +
               cli::format_number(pt.t_refactor) + " s, CHOLMOD given " + cli::format_number(pt.t_given) +
               " s, CHOLMOD METIS " + cli::format_number(pt.t_metis) + " s, columns updated " +
               cli::format_number(pt.up.stats.columns_updated_fraction));
    }
    cells.push_back(std::move(cell));
  }

  cli::Json j{{"command", "bench submesh"}, {"input", cli::input_json(opt, in)}};
  j["operator"] = bo.op;
  j["sets"] = bo.sets;
  j["n"] = n;
  j["nnz_A"] = A.nnz();
  j["nnz_L"] = L.symbolic->nnz_L;
  j["threads"] = threads;
  j["seed"] = opt.seed;
  j["patches"] = bo.patches;
  j["warm_heap"] = bo.warm_heap;
  j["operator_s"] = operator_s;
  j["global_factor_s"] = global_s;
  j["updater_setup_s"] = updater_s;
#ifdef LOCUS_HAVE_CHOLMOD
  j["cholmod"] = true;
#else
  j["cholmod"] = false;
#endif
  cli::Json jc = cli::Json::array();
  for (const Cell& c : cells) jc.push_back(cell_json(c));
  const std::string table = cell_table(opt, bo, n, threads, cells, jc);
  j["cells"] = jc;
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  std::cerr << table;
  if (opt.json) cli::emit(opt, j, {});
  return 0;
}

}  // namespace

void register_submesh_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add("submesh", "Factor-once update of a submesh factor vs refactoring (locus, CHOLMOD)",
                            [bo](const cli::CommonOptions& opt, const RunContext& ctx) {
                              return run_bench_submesh(opt, *bo, ctx);
                            });
  app->add_option("--fractions", bo->fractions, "Patch sizes as fractions of the vertices (default 0.1,0.25,0.5)");
  app->add_option("--patches", bo->patches, "Random BFS patches per fraction (default 5)")->check(CLI::Range(1, 10000));
  cli::drop_mesh_operator_option(app);
  app->add_option("--operator", bo->op, "laplacian (-L_C + eps M, default) or bilaplacian (K M^-1 K)");
  app->add_option("--sets", bo->sets, "bfs (patches around random seeds, default) or scattered (random vertices)")
      ->check(CLI::IsMember({"bfs", "scattered"}));
  app->add_flag("--updown", bo->updown, "Also time CHOLMOD row deletions (smallest fraction only)");
  app->add_option("--updown-cap", bo->updown_cap, "Seconds per patch for the row deletions (default 60)")
      ->check(CLI::Range(1.0, 3600.0));
  app->add_flag("--warm-heap", bo->warm_heap,
                "Serve all allocations from a heap that keeps freed pages (no first-touch faults after warm-up)");
}

}  // namespace locus::bench
