// Many-lane exact subset solve (kernels/solve_wide.hpp).
//
// Per supernode s (columns f..f+k-1, rows R[0..m), L_s column-major, ld = m),
// lanes in NB groups of 8 (Lane8), x rows in local numbering:
//   forward : x_s = L11^{-1} x_s;  x[R[k..m)] -= L21 x_s
//   backward: x_s = L11^{-T} (x_s - L21^T x[R[k..m)])
// The L21 products take four factor columns at a time, so each x row below the
// diagonal block is loaded once per four columns and each factor entry once.
#include "kernels/solve_wide.hpp"

#include <algorithm>
#include <string>

#include "kernels/lane8.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

template <int NB>
struct Row {
  Lane8 v[NB];
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

struct Super {
  int32_t k, m;
  const double* L;
  double* xs;         // the supernode's own k rows (contiguous in local numbering)
  const int32_t* rl;  // local rows of R[k..m)
};

// x[R[k + i]] -= sum_q L[k + i, j0 + q] x_s[j0 + q], q < NJ.
template <int NB, int NJ>
void forward_below(const Super& s, int32_t j0, double* x) {
  constexpr int W = 8 * NB;
  Row<NB> xj[NJ];
  const double* Lc[NJ];
  for (int q = 0; q < NJ; ++q) {
    xj[q] = Row<NB>::load(s.xs + static_cast<int64_t>(j0 + q) * W);
    Lc[q] = s.L + static_cast<int64_t>(j0 + q) * s.m;
  }
  for (int32_t i = s.k; i < s.m; ++i) {
    double* r = x + static_cast<int64_t>(s.rl[i - s.k]) * W;
    Row<NB> acc = Row<NB>::load(r);
    for (int q = 0; q < NJ; ++q) acc.fnma(Lc[q][i], xj[q]);
    acc.store(r);
  }
}

// x_s[j0 + q] -= sum_i L[k + i, j0 + q] x[R[k + i]], q < NJ.
template <int NB, int NJ>
void backward_below(const Super& s, int32_t j0, const double* x) {
  constexpr int W = 8 * NB;
  Row<NB> acc[NJ];
  const double* Lc[NJ];
  for (int q = 0; q < NJ; ++q) {
    acc[q] = Row<NB>::load(s.xs + static_cast<int64_t>(j0 + q) * W);
    Lc[q] = s.L + static_cast<int64_t>(j0 + q) * s.m;
  }
  for (int32_t i = s.k; i < s.m; ++i) {
    const Row<NB> t = Row<NB>::load(x + static_cast<int64_t>(s.rl[i - s.k]) * W);
    for (int q = 0; q < NJ; ++q) acc[q].fnma(Lc[q][i], t);
  }
  for (int q = 0; q < NJ; ++q) acc[q].store(s.xs + static_cast<int64_t>(j0 + q) * W);
}

template <int NB>
void forward_super(const Super& s, double* x) {
  constexpr int W = 8 * NB;
  // Diagonal block, row by row: x_i = (x_i - sum_{j<i} L_ij x_j) / L_ii.
  for (int32_t i = 0; i < s.k; ++i) {
    Row<NB> acc = Row<NB>::load(s.xs + static_cast<int64_t>(i) * W);
    for (int32_t j = 0; j < i; ++j)
      acc.fnma(s.L[i + static_cast<int64_t>(j) * s.m], Row<NB>::load(s.xs + static_cast<int64_t>(j) * W));
    acc.scale(1.0 / s.L[i + static_cast<int64_t>(i) * s.m]);
    acc.store(s.xs + static_cast<int64_t>(i) * W);
  }
  if (s.m == s.k) return;
  int32_t j0 = 0;
  for (; j0 + 4 <= s.k; j0 += 4) forward_below<NB, 4>(s, j0, x);
  switch (s.k - j0) {
    case 3: forward_below<NB, 3>(s, j0, x); break;
    case 2: forward_below<NB, 2>(s, j0, x); break;
    case 1: forward_below<NB, 1>(s, j0, x); break;
    default: break;
  }
}

template <int NB>
void backward_super(const Super& s, double* x) {
  constexpr int W = 8 * NB;
  if (s.m > s.k) {
    int32_t j0 = 0;
    for (; j0 + 4 <= s.k; j0 += 4) backward_below<NB, 4>(s, j0, x);
    switch (s.k - j0) {
      case 3: backward_below<NB, 3>(s, j0, x); break;
      case 2: backward_below<NB, 2>(s, j0, x); break;
      case 1: backward_below<NB, 1>(s, j0, x); break;
      default: break;
    }
  }
  // Diagonal block transposed, last row first: x_j = (x_j - sum_{i>j} L_ij x_i) / L_jj.
  for (int32_t j = s.k - 1; j >= 0; --j) {
    const double* Lj = s.L + static_cast<int64_t>(j) * s.m;
    Row<NB> acc = Row<NB>::load(s.xs + static_cast<int64_t>(j) * W);
    for (int32_t i = j + 1; i < s.k; ++i) acc.fnma(Lj[i], Row<NB>::load(s.xs + static_cast<int64_t>(i) * W));
    acc.scale(1.0 / Lj[j]);
    acc.store(s.xs + static_cast<int64_t>(j) * W);
  }
}

template <int NB>
void run(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
         WideSolveWorkspace& ws) {
  constexpr int W = 8 * NB;
  const SymbolicFactor& S = *F.symbolic;
  int32_t* local = ws.local.data();
  int64_t rows = 0;
  for (int32_t s : plan.touched)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) local[c] = static_cast<int32_t>(rows++);
  // Local rows of the sub-diagonal part of each supernode, gathered per supernode below.
  ws.x.assign(static_cast<size_t>(rows) * W, 0.0);
  double* x = ws.x.data();
  for (size_t k = 0; k < plan.rhs.size(); ++k) {
    double* r = x + static_cast<int64_t>(local[S.iperm[plan.rhs[k]]]) * W;
    for (int l = 0; l < W; ++l) r[l] += rhs[k * W + l];
  }
  std::vector<int32_t>& rl = ws.rows;
  auto super = [&](int32_t s) {
    const int32_t k = S.ncols(s), m = S.nrows(s);
    const int32_t* R = S.super_rows.data() + S.super_row_ptr[s];
    rl.resize(static_cast<size_t>(m - k));
    for (int32_t i = k; i < m; ++i) rl[i - k] = local[R[i]];
    return Super{k, m, F.block(s), x + static_cast<int64_t>(local[S.super_first_col[s]]) * W, rl.data()};
  };
  for (int32_t s : plan.forward) forward_super<NB>(super(s), x);
  for (int32_t s : plan.backward) backward_super<NB>(super(s), x);
  for (size_t k = 0; k < plan.outputs.size(); ++k) {
    const double* r = x + static_cast<int64_t>(local[S.iperm[plan.outputs[k]]]) * W;
    std::copy(r, r + W, out.begin() + static_cast<int64_t>(k) * W);
  }
}

}  // namespace

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
  if (out.size() != plan.outputs.size() * lanes)
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
