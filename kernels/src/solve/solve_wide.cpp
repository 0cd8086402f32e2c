// Many-lane exact subset solve (kernels/include/locus/kernels/solve/solve_wide.hpp).
//
// Per supernode s (columns f..f+k-1, rows R[0..m), L_s column-major, ld = m),
// lanes in NB groups of 8 (Lane8), x rows in local numbering:
//   forward : x_s = L11^{-1} x_s;  x[R[k..m)] -= L21 x_s
//   backward: x_s = L11^{-T} (x_s - L21^T x[R[k..m)])
// Both go through the block four factor columns at a time, each column read
// top to bottom (the order it is stored in): every factor entry is loaded once
// and every x row once per four columns.
#include "locus/kernels/solve/solve_wide.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/kernels/simd/lane8.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

template <int NB>
struct Row {
  Lane8 v[NB];
  static Row zero() {
    Row r;
    for (int b = 0; b < NB; ++b) r.v[b] = Lane8::zero();
    return r;
  }
  static Row load(const double* p) {
    Row r;
    for (int b = 0; b < NB; ++b) r.v[b] = Lane8::load(p + 8 * b);
    return r;
  }
  void store(double* p) const {
    for (int b = 0; b < NB; ++b) v[b].store(p + 8 * b);
  }
  void fnma(double a, const Row& x) {
    for (int b = 0; b < NB; ++b) v[b].fnma(a, x.v[b]);
  }
  void scale(double a) {
    for (int b = 0; b < NB; ++b) v[b].scale(a);
  }
};

// NB = 0: one lane, as a scalar, with the operations a Lane8 applies to each of
// its lanes (-(a x) + v, fused where the target has FMA: lane8.hpp; then v * a):
// the same numbers as any one lane of the wide solve (solve_planned_lane).
template <>
struct Row<0> {
  double v;
  static Row zero() { return {0.0}; }
  static Row load(const double* p) { return {*p}; }
  void store(double* p) const { *p = v; }
  void fnma(double a, const Row& x) { v = fnma_scalar(a, x.v, v); }
  void scale(double a) { v = v * a; }
};

// Doubles per row of x: 8 per group of lanes, 1 for the scalar lane.
template <int NB>
constexpr int kRowWidth = NB == 0 ? 1 : 8 * NB;

struct Super {
  int32_t k, m;
  const double* L;
  double* xs;         // the supernode's own k rows (contiguous in local numbering)
  const int32_t* rl;  // local rows of R[k..m)
};

// Rows i of x (at row_at(i)) -= sum_q Lc[q][i] xj[q], for i in [i0, i1).
// Both loops work on local copies of the caller's rows and column pointers:
// through the pointers, the compiler had to assume that the stores to x (and
// the loads from it) alias them, and kept the accumulators in memory, so every
// row paid a store-to-load round trip (perf: the 24-lane backward loop spilled
// 11 of 12 accumulators; an 8-lane solve took as long as a 24-lane one). Same
// operations in the same order: the results do not change.
template <int NB, int NJ, class RowAt>
void update_rows(const double* const* Lc_in, int32_t i0, int32_t i1, const Row<NB>* xj_in, RowAt row_at) {
  const double* Lc[NJ];
  Row<NB> xj[NJ];
  for (int q = 0; q < NJ; ++q) Lc[q] = Lc_in[q], xj[q] = xj_in[q];
  for (int32_t i = i0; i < i1; ++i) {
    double* r = row_at(i);
    Row<NB> acc = Row<NB>::load(r);
    for (int q = 0; q < NJ; ++q) acc.fnma(Lc[q][i], xj[q]);
    acc.store(r);
  }
}

// acc[q] -= sum_i Lc[q][i] (row i of x, at row_at(i)), for i in [i0, i1).
template <int NB, int NJ, class RowAt>
void gather_rows(const double* const* Lc_in, int32_t i0, int32_t i1, Row<NB>* acc_io, RowAt row_at) {
  const double* Lc[NJ];
  Row<NB> acc[NJ];
  for (int q = 0; q < NJ; ++q) Lc[q] = Lc_in[q], acc[q] = acc_io[q];
  for (int32_t i = i0; i < i1; ++i) {
    const Row<NB> t = Row<NB>::load(row_at(i));
    for (int q = 0; q < NJ; ++q) acc[q].fnma(Lc[q][i], t);
  }
  for (int q = 0; q < NJ; ++q) acc_io[q] = acc[q];
}

// Forward on the NJ columns j0.. of s: their own NJ x NJ triangle, then the
// rest of the diagonal block and the rows below, four columns per sweep so
// each factor entry is read once and each x row once per four columns.
template <int NB, int NJ>
void forward_columns(const Super& s, int32_t j0, double* x) {
  constexpr int W = kRowWidth<NB>;
  const double* Lc[NJ];
  for (int q = 0; q < NJ; ++q) Lc[q] = s.L + static_cast<int64_t>(j0 + q) * s.m;
  Row<NB> xj[NJ];
  for (int q = 0; q < NJ; ++q) {
    xj[q] = Row<NB>::load(s.xs + static_cast<int64_t>(j0 + q) * W);
    for (int p = 0; p < q; ++p) xj[q].fnma(Lc[p][j0 + q], xj[p]);
    xj[q].scale(1.0 / Lc[q][j0 + q]);
    xj[q].store(s.xs + static_cast<int64_t>(j0 + q) * W);
  }
  update_rows<NB, NJ>(Lc, j0 + NJ, s.k, xj, [&](int32_t i) { return s.xs + static_cast<int64_t>(i) * W; });
  update_rows<NB, NJ>(Lc, s.k, s.m, xj, [&](int32_t i) { return x + static_cast<int64_t>(s.rl[i - s.k]) * W; });
}

// Backward on the NJ columns j0.. of s, whose later columns are final:
// subtract the rows below and the later own rows, then the NJ x NJ triangle.
template <int NB, int NJ>
void backward_columns(const Super& s, int32_t j0, const double* x, bool from_zero) {
  constexpr int W = kRowWidth<NB>;
  const double* Lc[NJ];
  for (int q = 0; q < NJ; ++q) Lc[q] = s.L + static_cast<int64_t>(j0 + q) * s.m;
  Row<NB> acc[NJ];
  for (int q = 0; q < NJ; ++q) acc[q] = Row<NB>::zero();
  if (!from_zero)
    for (int q = 0; q < NJ; ++q) acc[q] = Row<NB>::load(s.xs + static_cast<int64_t>(j0 + q) * W);
  gather_rows<NB, NJ>(Lc, s.k, s.m, acc, [&](int32_t i) { return x + static_cast<int64_t>(s.rl[i - s.k]) * W; });
  gather_rows<NB, NJ>(Lc, j0 + NJ, s.k, acc, [&](int32_t i) { return s.xs + static_cast<int64_t>(i) * W; });
  for (int q = NJ - 1; q >= 0; --q) {
    for (int p = q + 1; p < NJ; ++p) acc[q].fnma(Lc[q][j0 + p], acc[p]);
    acc[q].scale(1.0 / Lc[q][j0 + q]);
    acc[q].store(s.xs + static_cast<int64_t>(j0 + q) * W);
  }
}

template <int NB>
void forward_super(const Super& s, double* x) {
  int32_t j0 = 0;
  for (; j0 + 4 <= s.k; j0 += 4) forward_columns<NB, 4>(s, j0, x);
  switch (s.k - j0) {
    case 3: forward_columns<NB, 3>(s, j0, x); break;
    case 2: forward_columns<NB, 2>(s, j0, x); break;
    case 1: forward_columns<NB, 1>(s, j0, x); break;
    default: break;
  }
}

// from_zero: s is outside the forward reach, so L^{-1} b is zero on its rows
// and they need not have been cleared (the same arithmetic: acc starts at +0).
template <int NB>
void backward_super(const Super& s, const double* x, bool from_zero) {
  // The last (partial) group first, then full groups of four downwards.
  int32_t j0 = s.k - s.k % 4;
  switch (s.k % 4) {
    case 3: backward_columns<NB, 3>(s, j0, x, from_zero); break;
    case 2: backward_columns<NB, 2>(s, j0, x, from_zero); break;
    case 1: backward_columns<NB, 1>(s, j0, x, from_zero); break;
    default: break;
  }
  for (j0 -= 4; j0 >= 0; j0 -= 4) backward_columns<NB, 4>(s, j0, x, from_zero);
}

template <int NB>
void run(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
         WideSolveWorkspace& ws) {
  constexpr int W = kRowWidth<NB>;
  const SymbolicFactor& S = *F.symbolic;
  int32_t* local = ws.local.data();
  int64_t rows = 0;
  for (int32_t s : plan.touched)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) local[c] = static_cast<int32_t>(rows++);
  // Local rows of the sub-diagonal part of each supernode, gathered per supernode below.
  // Only the forward reach is cleared: every other row is written by the
  // backward pass before it is read (a log-map region's rows are tens of MB).
  ws.x.resize(static_cast<size_t>(rows) * W);
  double* x = ws.x.data();
  for (int32_t s : plan.forward) {
    const int64_t r0 = local[S.super_first_col[s]];
    std::fill(x + r0 * W, x + (r0 + S.ncols(s)) * W, 0.0);
  }
  for (size_t k = 0; k < plan.rhs.size(); ++k) {
    double* r = x + static_cast<int64_t>(local[S.iperm[plan.rhs[k]]]) * W;
    for (int l = 0; l < W; ++l) r[l] += rhs[k * W + l];
  }
  HostVector<int32_t>& rl = ws.rows;
  auto super = [&](int32_t s) {
    const int32_t k = S.ncols(s), m = S.nrows(s);
    const int32_t* R = S.super_rows.data() + S.super_row_ptr[s];
    rl.resize(static_cast<size_t>(m - k));
    for (int32_t i = k; i < m; ++i) rl[i - k] = local[R[i]];
    return Super{k, m, F.block(s), x + static_cast<int64_t>(local[S.super_first_col[s]]) * W, rl.data()};
  };
  for (int32_t s : plan.forward) forward_super<NB>(super(s), x);
  // plan.backward is descending, plan.forward ascending: walk the latter from its end.
  auto fw = plan.forward.rbegin();
  for (int32_t s : plan.backward) {
    while (fw != plan.forward.rend() && *fw > s) ++fw;
    backward_super<NB>(super(s), x, fw == plan.forward.rend() || *fw != s);
  }
  ws.out_rows.resize(plan.outputs.size());
  for (size_t k = 0; k < plan.outputs.size(); ++k) ws.out_rows[k] = local[S.iperm[plan.outputs[k]]];
  if (out.empty()) return;
  for (size_t k = 0; k < plan.outputs.size(); ++k) {
    const double* r = x + static_cast<int64_t>(ws.out_rows[k]) * W;
    std::copy(r, r + W, out.begin() + static_cast<int64_t>(k) * W);
  }
}

}  // namespace

void solve_planned_lane(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs,
                        WideSolveWorkspace& ws) {
  if (!F.symbolic || plan.n != F.n()) fail(ErrorCode::BadUsage, "one-lane solve: the plan was made for another factor");
  if (plan.approximate)
    fail(ErrorCode::BadUsage, "one-lane solve: exact subset plans only (plan_subset_solve), got an approximate plan");
  if (rhs.size() != plan.rhs.size())
    fail(ErrorCode::BadUsage, "one-lane solve: " + std::to_string(rhs.size()) + " right-hand side values for a support of " +
                                  std::to_string(plan.rhs.size()));
  if (ws.local.size() != static_cast<size_t>(F.n())) ws.local.assign(static_cast<size_t>(F.n()), 0);
  run<0>(F, plan, rhs, {}, ws);
}

void solve_planned_wide(const NumericFactor& F, const SolvePlan& plan, int lanes, std::span<const double> rhs,
                        std::span<double> out, WideSolveWorkspace& ws) {
  if (!F.symbolic || plan.n != F.n()) fail(ErrorCode::BadUsage, "wide solve: the plan was made for another factor");
  if (plan.approximate)
    fail(ErrorCode::BadUsage, "wide solve: exact subset plans only (plan_subset_solve), got an approximate plan");
  if (lanes < 8 || lanes > kMaxWideLanes || lanes % 8 != 0)
    fail(ErrorCode::BadUsage, "wide solve: lanes must be 8, 16, 24 or 32 (got " + std::to_string(lanes) + ")");
  if (rhs.size() != plan.rhs.size() * lanes)
    fail(ErrorCode::BadUsage, "wide solve: " + std::to_string(rhs.size()) + " right-hand side values for a support of " +
                                  std::to_string(plan.rhs.size()) + " x " + std::to_string(lanes) + " lanes");
  if (!out.empty() && out.size() != plan.outputs.size() * lanes)
    fail(ErrorCode::BadUsage, "wide solve: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(plan.outputs.size()) + " x " + std::to_string(lanes) + " lanes");
  if (ws.local.size() != static_cast<size_t>(F.n())) ws.local.assign(static_cast<size_t>(F.n()), 0);
  switch (lanes / 8) {
    case 1: run<1>(F, plan, rhs, out, ws); break;
    case 2: run<2>(F, plan, rhs, out, ws); break;
    case 3: run<3>(F, plan, rhs, out, ws); break;
    default: run<4>(F, plan, rhs, out, ws); break;
  }
}

}  // namespace locus
