// Sections 1 and 2 of `locus-bench local` (bench_local.cpp describes them):
// single heat values by subset, union and full solves and CHOLMOD's Bset
// solve (thesis §4.6), the lanes of the multi-RHS solves, single entries of
// A^{-1}, and auto-diffusion at all vertices by selected inversion, the path
// walk and full solves.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/solve/selected_inversion.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "tools/bench/bench_local.hpp"

#ifdef LOCUS_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace locus::bench::local {
namespace {

using cli::Json;
using cli::Stopwatch;

#ifdef LOCUS_HAVE_CHOLMOD
// CHOLMOD with locus's ordering: supernodal factorization, then a simplicial
// LL^T copy for the Bset solves (conversion untimed).
class CholmodPeer {
 public:
  CholmodPeer(const CscMatrix& A, ConstView<int32_t> perm) {
    cholmod_start(&c_);
    c_.supernodal = CHOLMOD_SUPERNODAL;
    const size_t n = static_cast<size_t>(A.ncols);
    A_ = cholmod_allocate_sparse(n, n, static_cast<size_t>(A.nnz()), 1, 1, -1, CHOLMOD_REAL, &c_);
    check("cholmod_allocate_sparse");
    int* p = static_cast<int*>(A_->p);
    for (size_t k = 0; k <= n; ++k) p[k] = static_cast<int>(A.colptr[k]);
    std::copy(A.rowind.begin(), A.rowind.end(), static_cast<int*>(A_->i));
    std::copy(A.values.begin(), A.values.end(), static_cast<double*>(A_->x));
    std::vector<int> P(perm.begin(), perm.end());
    Stopwatch sw;
    L_ = cholmod_analyze_p(A_, P.data(), nullptr, 0, &c_);
    check("cholmod_analyze_p");
    cholmod_factorize(A_, L_, &c_);
    check("cholmod_factorize");
    factor_s = sw.seconds();
    Ls_ = cholmod_copy_factor(L_, &c_);
    cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, Ls_, &c_);
    check("cholmod_change_factor (to simplicial)");
    B_ = cholmod_zeros(n, 1, CHOLMOD_REAL, &c_);
    Bset_ = cholmod_allocate_sparse(n, 1, 2, 1, 1, 0, CHOLMOD_PATTERN, &c_);
    check("cholmod workspace");
  }
  ~CholmodPeer() {
    for (cholmod_factor** f : {&L_, &Ls_})
      if (*f) cholmod_free_factor(f, &c_);
    for (cholmod_sparse** s : {&A_, &Bset_, &Xset_})
      if (*s) cholmod_free_sparse(s, &c_);
    for (cholmod_dense** d : {&B_, &X_, &Y_, &E_})
      if (*d) cholmod_free_dense(d, &c_);
    cholmod_finish(&c_);
  }
  CholmodPeer(const CholmodPeer&) = delete;
  CholmodPeer& operator=(const CholmodPeer&) = delete;

  // x_j of A x = e_i by a Bset solve with pattern {i, j} (just {i} when i == j); seconds in *secs.
  double entry(int32_t i, int32_t j, double* secs) {
    int* bp = static_cast<int*>(Bset_->p);
    int* bi = static_cast<int*>(Bset_->i);
    bp[0] = 0;
    bi[0] = std::min(i, j);
    bi[1] = std::max(i, j);
    bp[1] = i == j ? 1 : 2;
    double* b = static_cast<double*>(B_->x);
    b[i] = 1.0;
    Stopwatch sw;
    cholmod_solve2(CHOLMOD_A, Ls_, B_, Bset_, &X_, &Xset_, &Y_, &E_, &c_);
    *secs = sw.seconds();
    b[i] = 0.0;
    check("cholmod_solve2 (Bset)");
    return static_cast<const double*>(X_->x)[j];
  }

  double factor_s = 0;

 private:
  void check(const char* what) {
    if (c_.status != CHOLMOD_OK) fail(ErrorCode::Internal, std::string(what) + " failed with status " + std::to_string(c_.status));
  }
  cholmod_common c_{};
  cholmod_sparse* A_ = nullptr;
  cholmod_factor *L_ = nullptr, *Ls_ = nullptr;
  cholmod_dense *B_ = nullptr, *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
  cholmod_sparse *Bset_ = nullptr, *Xset_ = nullptr;
};
#endif

double rel(double a, double ref) { return std::abs(a - ref) / std::max(std::abs(ref), 1e-300); }

using Pick = std::uniform_int_distribution<int32_t>;

// k random sources, sorted with repeats dropped (they would sum into one
// lane), and k random targets, drawn in that order.
std::pair<std::vector<int32_t>, std::vector<int32_t>> random_query(int k, Pick& pick, std::mt19937_64& rng) {
  std::vector<int32_t> src(static_cast<size_t>(k)), tgt(static_cast<size_t>(k));
  for (auto& v : src) v = pick(rng);
  for (auto& v : tgt) v = pick(rng);
  std::sort(src.begin(), src.end());
  src.erase(std::unique(src.begin(), src.end()), src.end());
  return {src, tgt};
}

// Lanes: one 8-lane subset solve against 8 one-lane solves with the same plan
// (support = 8 random sources, wanted = 8 random targets; lane k is e_{s_k}).
Json bench_lanes8(const NumericFactor& F, int rounds, Pick& pick, std::mt19937_64& rng, const RunContext& ctx) {
  std::vector<double> one_s, eight_s, r8;
  double worst8 = 0;
  SolveWorkspace lws;
  for (int p = 0; p < rounds; ++p) {
    ctx.check_cancel();
    const auto [src, tgt] = random_query(kLanes, pick, rng);
    const SolvePlan plan = plan_subset_solve(*F.symbolic, src, tgt);
    const size_t ns = src.size(), nt = tgt.size();
    std::vector<double> rhs8(ns * kLanes, 0.0), out8(nt * kLanes), out1(nt * kLanes), rhs1(ns), o1(nt);
    for (size_t k = 0; k < ns; ++k) rhs8[k * kLanes + k] = 1.0;
    Stopwatch sw;
    for (size_t lane = 0; lane < ns; ++lane) {
      std::fill(rhs1.begin(), rhs1.end(), 0.0);
      rhs1[lane] = 1.0;
      solve_planned(F, plan, rhs1, o1, lws);
      for (size_t q = 0; q < nt; ++q) out1[q * kLanes + lane] = o1[q];
    }
    const double t1 = sw.seconds();
    sw.restart();
    solve_planned8(F, plan, rhs8, out8, lws);
    const double t8 = sw.seconds();
    for (size_t q = 0; q < nt; ++q)
      for (size_t lane = 0; lane < ns; ++lane)
        worst8 = std::max(worst8, rel(out8[q * kLanes + lane], out1[q * kLanes + lane]));
    // Scale to 8 lanes when duplicate sources left fewer.
    one_s.push_back(t1 * kLanes / static_cast<double>(ns));
    eight_s.push_back(t8);
    r8.push_back(ratio(one_s.back(), t8));
  }
  return {{"one_lane_x8_s", cli::median(one_s)},
          {"eight_lane_s", cli::median(eight_s)},
          {"speedup_eight_lane_over_one_lane_x8", cli::median(r8)},
          {"max_rel_diff", worst8}};
}

// 24 lanes (the log map's batches are 7-22 sources): one wide
// subset solve of 24 sources x 24 targets, plan included, against three
// 8-lane solves of the same plan (the older path, the accuracy reference).
Json bench_lanes24(const NumericFactor& F, int rounds, Pick& pick, std::mt19937_64& rng, const RunContext& ctx) {
  constexpr int kWide = 24;
  std::vector<double> wide_s, three8_s, plan_s, fw, bw;
  double worst = 0;
  SolveWorkspace lws;
  WideSolveWorkspace wws;
  for (int p = 0; p < rounds; ++p) {
    ctx.check_cancel();
    const auto [src, tgt] = random_query(kWide, pick, rng);
    Stopwatch sw;
    const SolvePlan plan = plan_subset_solve(*F.symbolic, src, tgt);
    const double tp = sw.seconds();
    const size_t ns = src.size(), nt = tgt.size();
    std::vector<double> rhs(ns * kWide, 0.0), out(nt * kWide);
    for (size_t k = 0; k < ns; ++k) rhs[k * kWide + k] = 1.0;
    sw.restart();
    solve_planned_wide(F, plan, kWide, rhs, out, wws);
    const double tw = sw.seconds();
    // The same lanes in batches of 8 (lanes >= ns stay zero).
    // Differences relative to the largest value (a target far from every
    // source holds values near rounding level, where a pointwise ratio says nothing).
    std::vector<double> rhs8(ns * kLanes), out8(nt * kLanes);
    double t8 = 0, diff = 0, scale = 0;
    for (int b = 0; b < kWide / kLanes; ++b) {
      std::fill(rhs8.begin(), rhs8.end(), 0.0);
      for (size_t k = 0; k < ns; ++k)
        if (k / kLanes == static_cast<size_t>(b)) rhs8[k * kLanes + k % kLanes] = 1.0;
      sw.restart();
      solve_planned8(F, plan, rhs8, out8, lws);
      t8 += sw.seconds();
      for (size_t q = 0; q < nt; ++q)
        for (int l = 0; l < kLanes; ++l) {
          diff = std::max(diff, std::abs(out[q * kWide + b * kLanes + l] - out8[q * kLanes + l]));
          scale = std::max(scale, std::abs(out8[q * kLanes + l]));
        }
    }
    worst = std::max(worst, diff / std::max(scale, 1e-300));
    wide_s.push_back(tw);
    three8_s.push_back(t8);
    plan_s.push_back(tp);
    fw.push_back(static_cast<double>(plan.forward_columns));
    bw.push_back(static_cast<double>(plan.backward_columns));
  }
  return {{"plan_s", cli::median(plan_s)},
          {"wide_solve_s", cli::median(wide_s)},
          {"three_eight_lane_s", cli::median(three8_s)},
          {"forward_columns", cli::median(fw)},
          {"backward_columns", cli::median(bw)},
          {"max_diff_vs_eight_lane_rel_to_max", worst}};
}

// The heat operator's factor and what every section draws from: one sequence
// of seeded random vertices over all sections, in the report's order, a second
// one for the order of the contenders, and the CHOLMOD peer.
struct HeatValues {
  const NumericFactor& F;
  const Options& bo;
  const RunContext& ctx;
  const int32_t n = F.n();
#ifdef LOCUS_HAVE_CHOLMOD
  CholmodPeer& ch;
#endif
  std::mt19937_64 rng, order_rng;
  std::uniform_int_distribution<int32_t> pick{0, n - 1};
  HeatWorkspace ws{};

  Json pairs();
  Json everything();
  Json single_entry();
  Json adf_all();
};

// Single source / single target: subset, union, full and CHOLMOD, in a random order per pair.
Json HeatValues::pairs() {
  std::vector<double> sub_s, uni_s, full_s, ch_s, r_full, r_uni, r_ch, fw_cols, bw_cols, uni_cols;
  double worst_sub = 0, worst_uni = 0, worst_ch = 0;
  for (int p = 0; p < bo.pairs; ++p) {
    ctx.check_cancel();
    const int32_t s = pick(rng), tgt = pick(rng);
    const std::vector<int32_t> S{s}, T{tgt};
    double v_sub = 0, v_uni = 0, v_full = 0, v_ch = 0, t_sub = 0, t_uni = 0, t_full = 0, t_ch = 0;
    HeatExchangeStats st_sub, st_uni, st_full;
    // The contenders run back to back, in a random order per pair, so that none
    // systematically finds the cache warmed (or cleared) by another.
    const auto run = [&](int which) {
      Stopwatch sw;
      switch (which) {
        case 0: heat_exchange(F, S, T, HeatExchangeMethod::Subset, std::span<double>(&v_sub, 1), ws, &st_sub); t_sub = sw.seconds(); break;
        case 1: heat_exchange(F, S, T, HeatExchangeMethod::Union, std::span<double>(&v_uni, 1), ws, &st_uni); t_uni = sw.seconds(); break;
        case 2: heat_exchange(F, S, T, HeatExchangeMethod::Full, std::span<double>(&v_full, 1), ws, &st_full); t_full = sw.seconds(); break;
        default:
#ifdef LOCUS_HAVE_CHOLMOD
          // The first Bset call builds CHOLMOD's inverse permutation: warm it up once.
          if (p == 0) ch.entry(s, tgt, &t_ch);
          v_ch = ch.entry(s, tgt, &t_ch);
#endif
          break;
      }
    };
    std::array<int, 4> order{0, 1, 2, 3};
    std::shuffle(order.begin(), order.end(), order_rng);
    for (int which : order) run(which);
    sub_s.push_back(t_sub);
    uni_s.push_back(t_uni);
    full_s.push_back(t_full);
    fw_cols.push_back(static_cast<double>(st_sub.forward_columns));
    bw_cols.push_back(static_cast<double>(st_sub.backward_columns));
    uni_cols.push_back(static_cast<double>(st_uni.forward_columns + st_uni.backward_columns));
    r_full.push_back(ratio(t_full, t_sub));
    r_uni.push_back(ratio(t_uni, t_sub));
    worst_sub = std::max(worst_sub, rel(v_sub, v_full));
    worst_uni = std::max(worst_uni, rel(v_uni, v_full));
#ifdef LOCUS_HAVE_CHOLMOD
    ch_s.push_back(t_ch);
    r_ch.push_back(ratio(t_ch, t_sub));
    worst_ch = std::max(worst_ch, rel(v_ch, v_full));
#endif
  }
  Json pairs{{"count", bo.pairs},
             {"subset_s", cli::median(sub_s)},
             {"union_s", cli::median(uni_s)},
             {"full_s", cli::median(full_s)},
             {"speedup_full_over_subset", cli::median(r_full)},
             {"speedup_union_over_subset", cli::median(r_uni)},
             {"subset_forward_columns", cli::median(fw_cols)},
             {"subset_backward_columns", cli::median(bw_cols)},
             {"union_columns", cli::median(uni_cols)},
             {"max_rel_diff_subset_vs_full", worst_sub},
             {"max_rel_diff_union_vs_full", worst_uni}};
#ifdef LOCUS_HAVE_CHOLMOD
  pairs["cholmod_bset_s"] = cli::median(ch_s);
  pairs["speedup_cholmod_bset_over_subset"] = cli::median(r_ch);
  pairs["max_rel_diff_cholmod_vs_full"] = worst_ch;
#endif
  return pairs;
}

// "Everything": a subset plan whose support and wanted set are all vertices
// degrades to the full solve; its time against solve() on the same rhs.
Json HeatValues::everything() {
  std::vector<int32_t> all(n);
  for (int32_t v = 0; v < n; ++v) all[v] = v;
  Stopwatch sw;
  const SolvePlan plan = plan_subset_solve(*F.symbolic, all, all);
  const double plan_s = sw.seconds();
  std::vector<double> b(n), x(n), xf(n), work(solve_work_size(F, 1));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& v : b) v = u(rng);
  SolveWorkspace ews;
  std::vector<double> sub_t, full_t, re;
  double worst = 0;
  for (int rep = 0; rep < 5; ++rep) {
    sw.restart();
    solve_planned(F, plan, b, x, ews);
    sub_t.push_back(sw.seconds());
    xf = b;
    sw.restart();
    solve(F, xf, work);
    full_t.push_back(sw.seconds());
    re.push_back(ratio(sub_t.back(), full_t.back()));
  }
  for (int32_t v = 0; v < n; ++v) worst = std::max(worst, rel(x[v], xf[v]));
  return {{"plan_s", plan_s},
          {"subset_solve_s", cli::median(sub_t)},
          {"full_solve_s", cli::median(full_t)},
          {"ratio_subset_over_full", cli::median(re)},
          {"max_rel_diff", worst}};
}

// Single entries (A^{-1})_ii: the path walk, a subset solve, a full solve, CHOLMOD.
Json HeatValues::single_entry() {
  std::vector<double> walk_s, plan_s, dfull_s, dch_s, r_plan, r_full2, r_ch2;
  double worst_walk = 0, worst_plan = 0, worst_dch = 0;
  SolveWorkspace sws;
  for (int p = 0; p < bo.pairs; ++p) {
    ctx.check_cancel();
    const int32_t i = pick(rng);
    const std::vector<int32_t> I{i};
    double v_walk = 0, v_plan = 0, v_full = 0, v_ch = 0, t_walk = 0, t_plan = 0, t_full = 0, t_ch = 0;
    const auto run = [&](int which) {
      Stopwatch sw;
      switch (which) {
        case 0: v_walk = inverse_diagonal_entry(F, i, ws); t_walk = sw.seconds(); break;
        case 1: {
          const SolvePlan plan = plan_subset_solve(*F.symbolic, I, I);
          const double one = 1.0;
          solve_planned(F, plan, std::span<const double>(&one, 1), std::span<double>(&v_plan, 1), sws);
          t_plan = sw.seconds();
          break;
        }
        case 2: v_full = inverse_diagonal_entry_full(F, i, ws); t_full = sw.seconds(); break;
        default:
#ifdef LOCUS_HAVE_CHOLMOD
          v_ch = ch.entry(i, i, &t_ch);
#endif
          break;
      }
    };
    std::array<int, 4> order{0, 1, 2, 3};
    std::shuffle(order.begin(), order.end(), order_rng);
    for (int which : order) run(which);
    walk_s.push_back(t_walk);
    plan_s.push_back(t_plan);
    dfull_s.push_back(t_full);
    r_plan.push_back(ratio(t_plan, t_walk));
    r_full2.push_back(ratio(t_full, t_walk));
    worst_walk = std::max(worst_walk, rel(v_walk, v_full));
    worst_plan = std::max(worst_plan, rel(v_plan, v_full));
#ifdef LOCUS_HAVE_CHOLMOD
    dch_s.push_back(t_ch);
    r_ch2.push_back(ratio(t_ch, t_walk));
    worst_dch = std::max(worst_dch, rel(v_ch, v_full));
#endif
  }
  Json diag{{"count", bo.pairs},
            {"path_walk_s", cli::median(walk_s)},
            {"subset_solve_s", cli::median(plan_s)},
            {"full_s", cli::median(dfull_s)},
            {"speedup_subset_solve_over_walk", cli::median(r_plan)},
            {"speedup_full_over_walk", cli::median(r_full2)},
            {"max_rel_diff_walk_vs_full", worst_walk},
            {"max_rel_diff_subset_vs_full", worst_plan}};
#ifdef LOCUS_HAVE_CHOLMOD
  diag["cholmod_bset_s"] = cli::median(dch_s);
  diag["speedup_cholmod_bset_over_walk"] = cli::median(r_ch2);
  diag["max_rel_diff_cholmod_vs_full"] = worst_dch;
#endif
  return diag;
}

// ADF at every vertex: selected inversion, the path walk (extrapolated above
// --adf-subset-limit), full solves (extrapolated from --adf-sample).
Json HeatValues::adf_all() {
  Json adf;
  Stopwatch sw;
  const std::vector<double> sel = inverse_diagonal(selected_inversion(F, ctx));
  adf["selinv_s"] = sw.seconds();
  std::vector<int32_t> sample;  // empty = all
  if (n > bo.adf_subset_limit) {
    std::vector<int32_t> all(static_cast<size_t>(n));
    for (int32_t v = 0; v < n; ++v) all[v] = v;
    std::shuffle(all.begin(), all.end(), rng);
    sample.assign(all.begin(), all.begin() + bo.adf_subset_limit);
  }
  std::vector<double> walk(sample.empty() ? static_cast<size_t>(n) : sample.size());
  sw.restart();
  auto_diffusion(F, sample, AdfMethod::Subset, walk, ctx);
  const double walk_s_all = sw.seconds() * (sample.empty() ? 1.0 : static_cast<double>(n) / sample.size());
  adf["path_walk_s"] = walk_s_all;
  adf["path_walk_extrapolated"] = !sample.empty();
  double worst = 0;
  for (size_t k = 0; k < walk.size(); ++k) worst = std::max(worst, rel(sel[sample.empty() ? k : sample[k]], walk[k]));
  adf["max_rel_diff_selinv_vs_walk"] = worst;
  std::vector<double> one_full;
  for (int k = 0; k < bo.adf_sample; ++k) {
    ctx.check_cancel();
    const int32_t v = pick(rng);
    sw.restart();
    const double x = inverse_diagonal_entry_full(F, v, ws);
    one_full.push_back(sw.seconds());
    worst = std::max(worst, rel(sel[v], x));
  }
  adf["full_s_extrapolated"] = cli::median(one_full) * n;
  adf["full_sample"] = bo.adf_sample;
  adf["max_rel_diff_selinv_vs_full_sample"] = worst;
  adf["speedup_walk_over_selinv"] = ratio(walk_s_all, adf["selinv_s"].get<double>());
  adf["speedup_full_over_selinv"] = ratio(cli::median(one_full) * n, adf["selinv_s"].get<double>());
  return adf;
}

}  // namespace

Json bench_pairs(const Mesh& m, double t, const Options& bo, uint64_t seed, const RunContext& ctx) {
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{t}, ctx, ordering_by_name(bo.ordering));
  const NumericFactor& F = H.factors[0];
  Json j;
  j["t"] = t;
  j["ordering"] = bo.ordering;
  j["etree_height"] = H.symbolic->etree_height;
  j["super_etree_height"] = H.symbolic->super_etree_height;
  j["nnz_L"] = H.symbolic->nnz_L;
  j["locus_factor_s"] = H.order_s + H.analyze_s + H.numeric_s;
#ifdef LOCUS_HAVE_CHOLMOD
  CholmodPeer ch(heat_operator(m, t), H.symbolic->perm);
  j["cholmod_factor_s"] = ch.factor_s;
#endif
#ifdef LOCUS_HAVE_CHOLMOD
  HeatValues hv{F, bo, ctx, F.n(), ch, std::mt19937_64(seed), std::mt19937_64(seed + 17)};
#else
  HeatValues hv{F, bo, ctx, F.n(), std::mt19937_64(seed), std::mt19937_64(seed + 17)};
#endif
  j["pairs"] = hv.pairs();
  const int rounds = std::max(5, bo.pairs / 10);
  j["lanes"] = bench_lanes8(F, rounds, hv.pick, hv.rng, ctx);
  j["lanes24"] = bench_lanes24(F, rounds, hv.pick, hv.rng, ctx);
  j["everything"] = hv.everything();
  j["single_entry"] = hv.single_entry();
  if (!bo.skip_adf) j["adf_all"] = hv.adf_all();
  return j;
}

}  // namespace locus::bench::local
