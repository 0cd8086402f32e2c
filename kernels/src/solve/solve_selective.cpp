// Pruned approximate selective solve, 8 lanes (kernels/include/locus/kernels/solve/solve_selective.hpp).
#include "locus/kernels/solve/solve_selective.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/simd/lane8.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "supernode_block.hpp"

namespace locus {

namespace {

// Wide supernodes go through BLAS (as in kernels/src/solve/solve_full.cpp).
constexpr int kBlasCols = 24;

// Marks in ws.keep: bit 1 = kept column (Algorithm 2's K), bit 2 = column of a
// supernode in plan.forward_pruned (its y value is needed).
// Bit 4: column of a touched supernode (it has a row of the compact x).
constexpr uint8_t kKept = 1, kNeeded = 2, kTouched = 4;

// L y = b on supernode s, updating only the rows below whose y is needed. The rows
// below s lie in ancestors of s (a chain in the etree), and the needed supernodes
// are closed under descendants in the reach, so the needed rows are a prefix.
void forward_needed8(const NumericFactor& F, int32_t s, double* x8, double* tmp, const uint8_t* keep,
                     const int32_t* local) {
  const auto [f, k, m, rows, L] = supernode_block(F, s);
  int below = m - k;
  while (below > 0 && !(keep[rows[k + below - 1]] & kNeeded)) --below;
  double* xs = x8 + static_cast<int64_t>(local[f]) * kLanes;
  if (k >= kBlasCols) {
    const char r = 'R', lo = 'L', tr = 'T', nt = 'N', nu = 'N';
    const int eight = kLanes, kk = k, mi = m;
    const double one = 1.0, zero = 0.0;
    dtrsm_(&r, &lo, &tr, &nu, &eight, &kk, &one, L, &mi, xs, &eight);
    if (below > 0) {
      dgemm_(&nt, &tr, &eight, &below, &kk, &one, xs, &eight, L + k, &mi, &zero, tmp, &eight);
      for (int i = 0; i < below; ++i) {
        double* xr = x8 + static_cast<int64_t>(local[rows[k + i]]) * kLanes;
        Lane8 v = Lane8::load(xr);
        v.sub(Lane8::load(tmp + static_cast<int64_t>(i) * kLanes));
        v.store(xr);
      }
    }
    return;
  }
  for (int j = 0; j < k; ++j) {
    const double* Lj = L + static_cast<int64_t>(j) * m;
    Lane8 xj = Lane8::load(xs + j * kLanes);
    xj.scale(1.0 / Lj[j]);
    xj.store(xs + j * kLanes);
    for (int i = j + 1; i < k; ++i) {
      Lane8 xi = Lane8::load(xs + i * kLanes);
      xi.fnma(Lj[i], xj);
      xi.store(xs + i * kLanes);
    }
  }
  // Column by column into tmp: the row updates are independent (no dependency
  // chain through one accumulator), the column of L is read contiguously.
  if (below == 0) return;
  std::fill(tmp, tmp + static_cast<int64_t>(below) * kLanes, 0.0);
  for (int j = 0; j < k; ++j) {
    const double* Lj = L + static_cast<int64_t>(j) * m + k;
    const Lane8 xj = Lane8::load(xs + j * kLanes);
    for (int i = 0; i < below; ++i) {
      double* t = tmp + static_cast<int64_t>(i) * kLanes;
      Lane8 v = Lane8::load(t);
      v.fma(Lj[i], xj);
      v.store(t);
    }
  }
  for (int i = 0; i < below; ++i) {
    double* xr = x8 + static_cast<int64_t>(local[rows[k + i]]) * kLanes;
    Lane8 v = Lane8::load(xr);
    v.sub(Lane8::load(tmp + static_cast<int64_t>(i) * kLanes));
    v.store(xr);
  }
}

// acc -= sum_i a[i] * x[i * 8 ..]: four independent partial sums (a single
// accumulator makes every FMA wait for the previous one).
inline void dot_sub8(Lane8& acc, const double* a, const double* x, int count) {
  Lane8 p1 = Lane8::zero(), p2 = Lane8::zero(), p3 = Lane8::zero();
  int i = 0;
  for (; i + 4 <= count; i += 4) {
    acc.fnma(a[i], Lane8::load(x + static_cast<int64_t>(i) * kLanes));
    p1.fnma(a[i + 1], Lane8::load(x + static_cast<int64_t>(i + 1) * kLanes));
    p2.fnma(a[i + 2], Lane8::load(x + static_cast<int64_t>(i + 2) * kLanes));
    p3.fnma(a[i + 3], Lane8::load(x + static_cast<int64_t>(i + 3) * kLanes));
  }
  for (; i < count; ++i) acc.fnma(a[i], Lane8::load(x + static_cast<int64_t>(i) * kLanes));
  p1.fma(1.0, p2);
  p1.fma(1.0, p3);
  acc.fma(1.0, p1);
}

// L^T x = y on supernode s restricted to kept columns; entries outside K read as zero.
void backward_kept8(const NumericFactor& F, int32_t s, double* x8, double* tmp, const uint8_t* keep,
                    const int32_t* local) {
  const auto [f, k, m, rows, L] = supernode_block(F, s);
  const int below = m - k;
  for (int i = 0; i < below; ++i) {
    const int32_t r = rows[k + i];
    if (keep[r] & kKept) {
      Lane8::load(x8 + static_cast<int64_t>(local[r]) * kLanes).store(tmp + static_cast<int64_t>(i) * kLanes);
    } else {
      Lane8::zero().store(tmp + static_cast<int64_t>(i) * kLanes);
    }
  }
  double* xs = x8 + static_cast<int64_t>(local[f]) * kLanes;
  int kept_here = 0;
  for (int j = 0; j < k; ++j) kept_here += (keep[f + j] & kKept) != 0;
  if (kept_here == k && k >= kBlasCols) {  // the whole supernode is kept: one GEMM and one TRSM
    const char r = 'R', lo = 'L', nt = 'N', nu = 'N';
    const int eight = kLanes, kk = k, mi = m;
    const double one = 1.0, mone = -1.0;
    if (below > 0) dgemm_(&nt, &nt, &eight, &kk, &below, &mone, tmp, &eight, L + k, &mi, &one, xs, &eight);
    dtrsm_(&r, &lo, &nt, &nu, &eight, &kk, &one, L, &mi, xs, &eight);
    return;
  }
  for (int j = k - 1; j >= 0; --j) {
    if (!(keep[f + j] & kKept)) {
      Lane8::zero().store(xs + j * kLanes);
      continue;
    }
    const double* Lj = L + static_cast<int64_t>(j) * m;
    Lane8 acc = Lane8::load(xs + j * kLanes);
    dot_sub8(acc, Lj + k, tmp, below);
    dot_sub8(acc, Lj + j + 1, xs + static_cast<int64_t>(j + 1) * kLanes, k - j - 1);
    acc.scale(1.0 / Lj[j]);
    acc.store(xs + j * kLanes);
  }
}

}  // namespace

void solve_selective8(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs,
                      std::span<double> out, SolveWorkspace& ws) {
  if (!F.symbolic || plan.n != F.n()) fail(ErrorCode::BadUsage, "selective solve: plan made for another factor");
  if (!plan.approximate) fail(ErrorCode::BadUsage, "selective solve: needs a plan from plan_selective_solve");
  if (rhs.size() != plan.rhs.size() * kLanes)
    fail(ErrorCode::BadUsage, "selective solve: " + std::to_string(rhs.size()) +
                                  " right-hand side values for a support of " + std::to_string(plan.rhs.size()) + " x 8");
  if (out.size() != plan.outputs.size() * kLanes)
    fail(ErrorCode::BadUsage, "selective solve: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(plan.outputs.size()) + " x 8");
  const SymbolicFactor& S = *F.symbolic;
  if (ws.keep.size() < static_cast<size_t>(F.n())) ws.keep.assign(F.n(), 0);
  if (ws.local.size() < static_cast<size_t>(F.n())) ws.local.assign(F.n(), -1);
  // Rows of x: the touched supernodes' columns in ascending order (a supernode's
  // columns stay contiguous, as the dense kernels need); marked kTouched in keep
  // so that an output outside them reads zero, as in the full-length x.
  uint8_t* keep = ws.keep.data();
  int32_t* local = ws.local.data();
  int32_t rows = 0;
  for (int32_t s : plan.touched)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) {
      local[c] = rows++;
      keep[c] = kTouched;
    }
  const size_t nx = static_cast<size_t>(rows) * kLanes;
  if (ws.x.size() < nx) ws.x.assign(nx, 0.0);
  const size_t nt = static_cast<size_t>(S.max_super_rows) * kLanes;
  if (ws.tmp.size() < nt) ws.tmp.resize(nt);
  blas::SingleThreaded single;
  double* x = ws.x.data();
  double* tmp = ws.tmp.data();
  for (size_t k = 0; k < plan.rhs.size(); ++k) {  // b is added: repeated support entries sum
    const int32_t c = S.iperm[plan.rhs[k]];
    if (!(keep[c] & kTouched)) fail(ErrorCode::Internal, "selective solve: a right-hand side outside the plan");
    for (int l = 0; l < kLanes; ++l) x[static_cast<int64_t>(local[c]) * kLanes + l] += rhs[k * kLanes + l];
  }
  // Forward over the pruned reach: every supernode feeding a kept entry, with all
  // of its own descendants in the reach (they are pruned-in too), so kept y is exact;
  // rows of supernodes outside it are not updated (nothing reads them).
  for (int32_t s : plan.forward_pruned)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) keep[c] |= kNeeded;
  for (int32_t s : plan.forward_pruned) forward_needed8(F, s, x, tmp, keep, local);
  for (int32_t c : plan.kept_cols) keep[c] |= kKept;
  for (int32_t s : plan.backward) backward_kept8(F, s, x, tmp, keep, local);
  for (size_t k = 0; k < plan.outputs.size(); ++k) {
    const int32_t c = S.iperm[plan.outputs[k]];
    for (int l = 0; l < kLanes; ++l)
      out[k * kLanes + l] = (keep[c] & kTouched) ? x[static_cast<int64_t>(local[c]) * kLanes + l] : 0.0;
  }
  // The rhs, the forward updates (ancestors of the reach) and the backward all
  // stay inside plan.touched: clearing its rows and marks cleans the workspace
  // (the kept columns and the pruned reach are columns of touched supernodes).
  std::fill(ws.x.begin(), ws.x.begin() + static_cast<int64_t>(nx), 0.0);
  for (int32_t c : plan.kept_cols) keep[c] = 0;
  for (int32_t s : plan.touched)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) {
      keep[c] = 0;
      local[c] = -1;
    }
}

int64_t factor_entries(const SymbolicFactor& S) {
  int64_t e = 0;
  for (int32_t s = 0; s < S.ns; ++s) {
    const int64_t k = S.ncols(s), m = S.nrows(s);
    e += k * (k + 1) / 2 + (m - k) * k;
  }
  return e;
}

int64_t selective_solve_reads(const SymbolicFactor& S, const SolvePlan& plan, std::vector<uint8_t>& mark) {
  if (plan.n != S.n || !plan.approximate)
    fail(ErrorCode::BadUsage, "selective solve reads: needs an approximate plan of this factor");
  if (mark.size() < static_cast<size_t>(S.n)) mark.assign(S.n, 0);
  for (int32_t s : plan.forward_pruned)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) mark[c] = kNeeded;
  for (int32_t c : plan.kept_cols) mark[c] |= kKept;
  int64_t reads = 0;
  for (int32_t s : plan.forward_pruned) {  // as forward_needed8
    const int64_t k = S.ncols(s), m = S.nrows(s);
    const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
    int64_t below = m - k;
    while (below > 0 && !(mark[rows[k + below - 1]] & kNeeded)) --below;
    reads += k * (k + 1) / 2 + below * k;
  }
  for (int32_t s : plan.backward) {  // as backward_kept8
    const int32_t f = S.super_first_col[s];
    const int64_t k = S.ncols(s), m = S.nrows(s);
    int64_t kept_here = 0;
    for (int64_t j = 0; j < k; ++j) kept_here += (mark[f + j] & kKept) != 0;
    if (kept_here == k && k >= kBlasCols) {
      reads += k * (k + 1) / 2 + (m - k) * k;
      continue;
    }
    for (int64_t j = 0; j < k; ++j)
      if (mark[f + j] & kKept) reads += (m - k) + (k - j);
  }
  for (int32_t c : plan.kept_cols) mark[c] = 0;
  for (int32_t s : plan.forward_pruned)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c) mark[c] = 0;
  return reads;
}

}  // namespace locus
