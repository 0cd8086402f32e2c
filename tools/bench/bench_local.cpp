// `locus-bench local MESH [--subdivide K] [--threads N] --json`: the local
// solves of thesis chapter 4 against full solves and CHOLMOD, in one run.
//
// 1. Single source / single target heat value (§4.6, Fig. 4.9/4.12): heat
//    operator M - t L_C factored once; for --pairs random (source, target)
//    pairs, back to back per pair:
//      subset  — separate etree subtrees: forward from the source, backward to
//                the target (plan + solve, pipelines/heat_exchange)
//      union   — one subtree of {source, target} for both passes
//      full    — a full solve
//      CHOLMOD — cholmod_solve2 with Bset = {source, target} (b = 0 at the
//                target) on a simplicial copy of CHOLMOD's factor (the
//                supernodal-to-simplicial conversion is done once, untimed).
//                CHOLMOD is given locus's METIS ordering (cholmod_analyze_p),
//                so both walk the same elimination tree.
//    Also the single-entry value (A^{-1})_ii at --pairs random vertices: the
//    forward-only path walk (pipelines/adf), a subset solve (plan + forward +
//    backward), CHOLMOD Bset = {i}, a full solve. Reported: medians, the median
//    of the per-pair ratios, columns visited, the etree height. Lanes: an
//    8-lane subset solve against 8 one-lane ones, and a 24-lane one (24
//    random sources and targets, kernels/solve_wide) against three 8-lane ones.
// 2. Auto-diffusion at ALL vertices: selected inversion (kernels/
//    selected_inversion) vs the per-vertex path walk over all vertices (both
//    with --threads) vs full solves (median of --adf-sample single full solves
//    times n, one thread: an extrapolation). Above --adf-subset-limit vertices
//    the path walk is also extrapolated from a random sample of that many.
// 3. Patch parameterization (§4.4, Figs. 4.6/4.7): regularized Laplacian
//    factored once; for each patch size in --patch-sizes (sizes above n/2
//    skipped) and --patch-centers random centers:
//      local   — pipelines/patch_param: BFS patch, eq. 4.6 data, 8-lane subset
//                solve on the global factor, normalization, flip count
//      patch system — the same BFS patch extracted as a mesh, its own
//                regularized Laplacian, METIS ordering + symbolic + numeric
//                factorization, eq. 4.6 data and an 8-lane full solve (the
//                classical approach; BFS growing is common to both and timed
//                in both).
// 4. Circle-boundary patch map (pipelines/patch_param_circle): the same
//    patches with holes filled and the boundary fixed on a circle; the local
//    route updates the global factor to K_II (factor once, chapter 5), the
//    peer orders and factors K_II from scratch; both solve the same system.
// Ratios are peer / locus-local (> 1: the local solve is faster).
#include <oneapi/tbb/info.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <random>
#include <sstream>

#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/selected_inversion.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/param/patch_param_circle.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/cli/vertex_list.hpp"

#ifdef LOCUS_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;

struct Options {
  std::string t_text = "1h2";
  int pairs = 100;
  int adf_sample = 100;
  int adf_subset_limit = 300000;
  std::string patch_sizes = "2000,10000,30000,50000";
  int patch_centers = 5;
  bool skip_adf = false, skip_patch = false;
  // The heat section's ordering: auto (the library's default), or metis
  // (METIS_NodeND, the ordering before issue 26), nd, amd: the local solves
  // of two orderings compared in one binary.
  std::string ordering = "auto";
};

double ratio(double peer, double mine) { return mine > 0 ? peer / mine : 0.0; }

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

// ------------------------------------------------------- 1. heat values ----

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

// 24 lanes (issue 26; the log map's batches are 7-22 sources): one wide
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

Json bench_pairs(const Mesh& m, double t, const Options& bo, uint64_t seed, const RunContext& ctx) {
  const HeatFactors H = factor_heat_operators(m, std::vector<double>{t}, ctx, ordering_by_name(bo.ordering));
  const NumericFactor& F = H.factors[0];
  const int32_t n = F.n();
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
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  std::mt19937_64 order_rng(seed + 17);
  HeatWorkspace ws;
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
  j["pairs"] = pairs;

  const int rounds = std::max(5, bo.pairs / 10);
  j["lanes"] = bench_lanes8(F, rounds, pick, rng, ctx);
  j["lanes24"] = bench_lanes24(F, rounds, pick, rng, ctx);

  // "Everything": a subset plan whose support and wanted set are all vertices
  // degrades to the full solve; its time against solve() on the same rhs.
  {
    std::vector<int32_t> all(n);
    for (int32_t v = 0; v < n; ++v) all[v] = v;
    Stopwatch sw;
    const SolvePlan plan = plan_subset_solve(*H.symbolic, all, all);
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
    j["everything"] = {{"plan_s", plan_s},
                       {"subset_solve_s", cli::median(sub_t)},
                       {"full_solve_s", cli::median(full_t)},
                       {"ratio_subset_over_full", cli::median(re)},
                       {"max_rel_diff", worst}};
  }

  // Single entries (A^{-1})_ii.
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
          const SolvePlan plan = plan_subset_solve(*H.symbolic, I, I);
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
  j["single_entry"] = diag;

  // 2. ADF at every vertex.
  if (!bo.skip_adf) {
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
    j["adf_all"] = adf;
  }
  return j;
}

// ------------------------------------------------ 3. patch parameterization ----

// The --patch-sizes that fit a mesh of n vertices (10 .. n/2), logged when skipped.
std::vector<int32_t> patch_sizes(const Options& bo, int32_t n) {
  std::vector<int32_t> sizes;
  for (const std::string& item : cli::split_list(bo.patch_sizes, "--patch-sizes")) {
    const int32_t size = static_cast<int32_t>(std::stol(item));
    if (size < 10 || size > n / 2) cli::log("bench local: patch size " + item + " skipped (n = " + std::to_string(n) + ")");
    else sizes.push_back(size);
  }
  return sizes;
}

// F: the factor of m's regularized Laplacian (shared with section 4).
Json bench_patches(const Mesh& m, const NumericFactor& F, const Options& bo, uint64_t seed,
                   const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  Json j;
  Stopwatch sw;
  j["etree_height"] = F.symbolic->etree_height;
  const PatchGrower g = prepare_patch_grower(m);
  PatchWorkspace pws;
  SolveWorkspace ws;
  std::mt19937_64 rng(seed ^ 0x5bd1e995ULL);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  Json rows = Json::array();
  for (const int32_t size : patch_sizes(bo, n)) {
    std::vector<double> local_s, sys_s, sys_factor_s, r, np, flips_local, flips_sys, fw, bw, grow_s, solve_s;
    for (int c = 0; c < bo.patch_centers; ++c) {
      ctx.check_cancel();
      const int32_t center = pick(rng);
      // (local) from the global factor.
      sw.restart();
      const PatchParam P = parameterize_patch(F, g, center, size, pws, ws);
      local_s.push_back(sw.seconds());
      grow_s.push_back(P.grow_s);
      solve_s.push_back(P.solve_s);
      // (patch system) extract, assemble, order, factor, solve.
      sw.restart();
      const MeshPatch patch = grow_patch(g, center, ring_patch(size), pws);
      const std::vector<std::vector<int32_t>> loops = boundary_loops(patch.mesh);
      size_t best = 0;
      for (size_t l = 1; l < loops.size(); ++l)
        if (loops[l].size() > loops[best].size()) best = l;
      const CscMatrix Kp = regularized_laplacian(patch.mesh);
      Stopwatch fsw;
      const NumericFactor Fp = factorize(analyze(Kp, order_matrix(Kp)), Kp);
      const double fs = fsw.seconds();
      const std::vector<double> b = circle_neumann_rhs(patch.mesh, loops[best]);
      const size_t pn = patch.vertices.size();
      std::vector<double> x8(pn * kLanes, 0.0);
      for (size_t k = 0; k < loops[best].size(); ++k) {
        x8[static_cast<size_t>(loops[best][k]) * kLanes] = b[2 * k];
        x8[static_cast<size_t>(loops[best][k]) * kLanes + 1] = b[2 * k + 1];
      }
      solve8(Fp, x8);
      std::vector<double> uv(2 * pn);
      for (size_t k = 0; k < pn; ++k) {
        uv[2 * k] = x8[k * kLanes];
        uv[2 * k + 1] = x8[k * kLanes + 1];
      }
      normalize_uv(uv);
      const UvFlips fl = count_uv_flips(patch.mesh, uv);
      sys_s.push_back(sw.seconds());
      sys_factor_s.push_back(fs);
      r.push_back(ratio(sys_s.back(), local_s.back()));
      np.push_back(static_cast<double>(P.patch.vertices.size()));
      flips_local.push_back(static_cast<double>(P.flips.flipped));
      flips_sys.push_back(static_cast<double>(fl.flipped));
      fw.push_back(static_cast<double>(P.forward_columns));
      bw.push_back(static_cast<double>(P.backward_columns));
    }
    rows.push_back({{"patch_size", size},
                    {"patch_vertices", cli::median(np)},
                    {"centers", bo.patch_centers},
                    {"local_s", cli::median(local_s)},
                    {"local_grow_s", cli::median(grow_s)},
                    {"local_solve_s", cli::median(solve_s)},
                    {"patch_system_s", cli::median(sys_s)},
                    {"patch_system_factor_s", cli::median(sys_factor_s)},
                    {"speedup_patch_system_over_local", cli::median(r)},
                    {"forward_columns", cli::median(fw)},
                    {"backward_columns", cli::median(bw)},
                    {"max_flips_local", *std::max_element(flips_local.begin(), flips_local.end())},
                    {"max_flips_patch_system", *std::max_element(flips_sys.begin(), flips_sys.end())}});
    cli::log("bench local: patches of " + std::to_string(size) + " done");
  }
  j["sizes"] = rows;
  return j;
}

// ------------------------------ 4. circle-boundary patch map (factor once) ----
// The same BFS patches (holes filled) with the boundary fixed on a circle:
//   local — pipelines/patch_param_circle: K_II's factor by the factor-once
//           update of the global factor (updater built once per mesh, reported
//           as updater_setup_s), Dirichlet data, refinement, flips;
//   patch system — the same patch and data, K_II extracted and factored from
//           scratch (METIS ordering + symbolic + numeric), the same solve.
// Both time patch growing, the system, the factorization and the solve; the
// two maps must agree (max_uv_difference, relative to the map's radius).
Json bench_circle_patches(const Mesh& m, const CscMatrix& K, const NumericFactor& F, const Options& bo,
                          uint64_t seed, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  Json j;
  Stopwatch sw;
  const PatchGrower g = prepare_patch_grower(m);
  sw.restart();
  CirclePatchParameterizer cp(F, K, g);
  j["updater_setup_s"] = sw.seconds();
  DiskPatchWorkspace dws;
  std::mt19937_64 rng(seed ^ 0x5bd1e995ULL);
  std::uniform_int_distribution<int32_t> pick(0, n - 1);
  Json rows = Json::array();
  for (const int32_t size : patch_sizes(bo, n)) {
    std::vector<double> local_s, sys_s, r, np, holes, flips_local, flips_sys, upd_s, fac_s, diff, steps;
    std::vector<double> grow_s, system_s, solve_s, check_s;
    int refused = 0;
    for (int c = 0, tries = 0; c < bo.patch_centers && tries < 20 * bo.patch_centers; ++tries) {
      ctx.check_cancel();
      const int32_t center = pick(rng);
      sw.restart();
      CirclePatchParam P;
      try {
        P = cp.parameterize(center, size, ctx);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::BadInput) throw;
        ++refused;  // not disk-like: the Neumann method's territory
        continue;
      }
      local_s.push_back(sw.seconds());
      ++c;
      // (patch system) the same patch, data and solve; K_II factored from scratch.
      sw.restart();
      const DiskPatch d = grow_disk_patch(g, center, size, dws);
      const CircleDirichletSystem sys = circle_dirichlet_system(K, d, dws);
      Stopwatch fsw;
      const CscMatrix Kii = principal_submatrix(K, sys.interior);
      const NumericFactor Fp = factorize(analyze(Kii, order_matrix(Kii)), Kii);
      const double fs = fsw.seconds();
      std::vector<double> uv_int(2 * sys.interior.size());
      const int st = solve_circle_dirichlet(Fp, Kii, sys, uv_int);
      std::vector<double> uv = assemble_patch_uv(d, sys, uv_int);
      normalize_uv(uv);
      const UvFlips fl = count_uv_flips(d.patch.mesh, uv);
      sys_s.push_back(sw.seconds());
      r.push_back(ratio(sys_s.back(), local_s.back()));
      double dmax = 0;
      for (size_t k = 0; k < uv.size() && k < P.uv.size(); ++k) dmax = std::max(dmax, std::abs(uv[k] - P.uv[k]));
      diff.push_back(uv.size() == P.uv.size() ? dmax : 1.0);
      np.push_back(static_cast<double>(P.disk.patch.vertices.size()));
      holes.push_back(static_cast<double>(P.disk.holes_filled));
      flips_local.push_back(static_cast<double>(P.flips.flipped + P.flips.degenerate));
      flips_sys.push_back(static_cast<double>(fl.flipped + fl.degenerate));
      upd_s.push_back(P.update_s);
      grow_s.push_back(P.grow_s);
      system_s.push_back(P.system_s);
      solve_s.push_back(P.solve_s);
      check_s.push_back(P.check_s);
      fac_s.push_back(fs);
      steps.push_back(std::max(P.refinement_steps, st));
    }
    if (local_s.empty()) {
      rows.push_back({{"patch_size", size}, {"refused_not_disk", refused}});
      continue;
    }
    rows.push_back({{"patch_size", size},
                    {"patch_vertices", cli::median(np)},
                    {"centers", local_s.size()},
                    {"refused_not_disk", refused},
                    {"holes_filled_median", cli::median(holes)},
                    {"local_s", cli::median(local_s)},
                    {"local_grow_s", cli::median(grow_s)},
                    {"local_system_s", cli::median(system_s)},
                    {"local_update_s", cli::median(upd_s)},
                    {"local_solve_s", cli::median(solve_s)},
                    {"local_check_s", cli::median(check_s)},
                    {"patch_system_s", cli::median(sys_s)},
                    {"patch_system_factor_s", cli::median(fac_s)},
                    {"speedup_patch_system_over_local", cli::median(r)},
                    {"min_speedup", *std::min_element(r.begin(), r.end())},
                    {"max_uv_difference", *std::max_element(diff.begin(), diff.end())},
                    {"max_refinement_steps", *std::max_element(steps.begin(), steps.end())},
                    {"max_flips_local", *std::max_element(flips_local.begin(), flips_local.end())},
                    {"max_flips_patch_system", *std::max_element(flips_sys.begin(), flips_sys.end())}});
    cli::log("bench local: circle patches of " + std::to_string(size) + " done");
  }
  j["sizes"] = rows;
  return j;
}

int run_bench_local(const cli::CommonOptions& opt, const Options& bo, const RunContext& ctx) {
  const cli::TimeSpec spec = cli::parse_time_spec(bo.t_text);
  cli::Input in = cli::load_input(opt, ctx);
  const Mesh& m = in.mesh;
  check_requirements(m, MeshRequirements{});
  const double h = mean_edge_length(m);
  const int threads = opt.threads > 0 ? opt.threads : tbb::info::default_concurrency();
  Json j{{"command", "bench local"}, {"input", cli::input_json(opt, in)}};
  j["n"] = m.num_vertices();
  j["threads"] = threads;
  j["seed"] = opt.seed;
  j["h"] = h;
  cli::log("bench local: heat values (" + std::to_string(bo.pairs) + " pairs)");
  j["heat"] = bench_pairs(m, spec.resolve(h), bo, opt.seed, ctx);
  if (!bo.skip_patch) {
    cli::log("bench local: patch parameterization");
    Stopwatch fsw;
    const CscMatrix K = regularized_laplacian(m);
    const NumericFactor F = factorize(analyze(K, order_matrix(K)), K, ctx);
    const double global_factor_s = fsw.seconds();
    j["patch"] = bench_patches(m, F, bo, opt.seed, ctx);
    j["patch"]["global_factor_s"] = global_factor_s;
    cli::log("bench local: circle-boundary patch map (factor-once update)");
    j["patch_circle"] = bench_circle_patches(m, K, F, bo, opt.seed, ctx);
  }
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  std::cerr << j.dump(1) << "\n";
  if (opt.json) cli::emit(opt, j, {});
  return 0;
}

}  // namespace

void register_local_bench(cli::CommandTable& table) {
  auto bo = std::make_shared<Options>();
  CLI::App* app = table.add(
      "local", "Local solves (thesis ch. 4): heat values, auto-diffusion at all vertices, patch parameterization",
      [bo](const cli::CommonOptions& opt, const RunContext& ctx) { return run_bench_local(opt, *bo, ctx); });
  app->add_option("--t", bo->t_text, "Diffusion time of the heat operator (default 1h2)");
  app->add_option("--pairs", bo->pairs, "Random pairs / vertices for the single values (default 100)")
      ->check(CLI::Range(1, 1000000));
  app->add_option("--adf-sample", bo->adf_sample, "Full solves to extrapolate the all-vertex full method (default 100)")
      ->check(CLI::Range(1, 1000000));
  app->add_option("--adf-subset-limit", bo->adf_subset_limit,
                  "Above this n the all-vertex path walk is extrapolated from this many random vertices (default 300000)")
      ->check(CLI::Range(1, 1 << 30));
  app->add_option("--patch-sizes", bo->patch_sizes, "Patch vertex counts (default 2000,10000,30000,50000)");
  app->add_option("--patch-centers", bo->patch_centers, "Random centers per patch size (default 5)")
      ->check(CLI::Range(1, 10000));
  app->add_flag("--skip-adf", bo->skip_adf, "Skip the all-vertex auto-diffusion section");
  app->add_option("--ordering", bo->ordering, "Ordering of the heat section: auto (default), metis, nd, amd")
      ->check(CLI::IsMember({"auto", "metis", "nd", "amd"}));
  app->add_flag("--skip-patch", bo->skip_patch, "Skip the patch parameterization section");
}

}  // namespace locus::bench
