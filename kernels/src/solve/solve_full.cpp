// Supernodal triangular solves, 1 and 8 lanes (kernels/include/locus/kernels/solve/solve_full.hpp).
//
// Per supernode s (columns f..f+k-1, rows R[0..m), L_s column-major, ld = m):
//   forward : x_s = L11^{-1} x_s;  x[R[k..m)] -= L21 x_s
//   backward: x_s = L11^{-T} (x_s - L21^T x[R[k..m)])
// Small supernodes use plain loops (BLAS call overhead would dominate); wide
// ones (k >= kBlasCols) call dtrsv/dgemv or, for 8 lanes, dtrsm/dgemm on the
// interleaved block seen as a column-major 8 x k matrix.
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <vector>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/simd/lane8.hpp"
#include "locus/error.hpp"
#include "supernode_block.hpp"

namespace locus {

namespace {
constexpr int kBlasCols = 24;

}  // namespace

void forward_supernode(const NumericFactor& F, int32_t s, double* x, double* tmp) {
  const SupernodeBlock b = supernode_block(F, s);
  double* xs = x + b.f;
  const int64_t m = b.m;
  const int below = b.m - b.k;
  if (b.k >= kBlasCols) {
    const char lo = 'L', nt = 'N', nu = 'N';
    const int one_i = 1, k = b.k, mi = b.m;
    dtrsv_(&lo, &nt, &nu, &k, b.L, &mi, xs, &one_i);
    if (below > 0) {
      const double one = 1.0, zero = 0.0;
      dgemv_(&nt, &below, &k, &one, b.L + b.k, &mi, xs, &one_i, &zero, tmp, &one_i);
      for (int i = 0; i < below; ++i) x[b.rows[b.k + i]] -= tmp[i];
    }
    return;
  }
  for (int j = 0; j < b.k; ++j) {
    const double* Lj = b.L + j * m;
    const double xj = xs[j] / Lj[j];
    xs[j] = xj;
    for (int i = j + 1; i < b.k; ++i) xs[i] -= Lj[i] * xj;
  }
  if (below == 0) return;
  if (b.k == 1) {
    const double xj = xs[0];
    for (int i = 1; i < b.m; ++i) x[b.rows[i]] -= b.L[i] * xj;
    return;
  }
  std::fill(tmp, tmp + below, 0.0);
  for (int j = 0; j < b.k; ++j) {
    const double* Lj = b.L + j * m + b.k;
    const double xj = xs[j];
    for (int i = 0; i < below; ++i) tmp[i] += Lj[i] * xj;
  }
  for (int i = 0; i < below; ++i) x[b.rows[b.k + i]] -= tmp[i];
}

void backward_supernode(const NumericFactor& F, int32_t s, double* x, double* tmp) {
  const SupernodeBlock b = supernode_block(F, s);
  double* xs = x + b.f;
  const int64_t m = b.m;
  const int below = b.m - b.k;
  for (int i = 0; i < below; ++i) tmp[i] = x[b.rows[b.k + i]];
  if (b.k >= kBlasCols) {
    const char lo = 'L', tr = 'T', nu = 'N';
    const int one_i = 1, k = b.k, mi = b.m;
    if (below > 0) {
      const double one = 1.0, mone = -1.0;
      dgemv_(&tr, &below, &k, &mone, b.L + b.k, &mi, tmp, &one_i, &one, xs, &one_i);
    }
    dtrsv_(&lo, &tr, &nu, &k, b.L, &mi, xs, &one_i);
    return;
  }
  for (int j = b.k - 1; j >= 0; --j) {
    const double* Lj = b.L + j * m;
    double acc = xs[j];
    for (int i = 0; i < below; ++i) acc -= Lj[b.k + i] * tmp[i];
    for (int i = j + 1; i < b.k; ++i) acc -= Lj[i] * xs[i];
    xs[j] = acc / Lj[j];
  }
}

void forward_supernode8(const NumericFactor& F, int32_t s, double* x8, double* tmp) {
  const SupernodeBlock b = supernode_block(F, s);
  double* xs = x8 + static_cast<int64_t>(b.f) * kLanes;
  const int64_t m = b.m;
  const int below = b.m - b.k;
  if (b.k >= kBlasCols) {
    const char r = 'R', lo = 'L', tr = 'T', nt = 'N', nu = 'N';
    const int eight = kLanes, k = b.k, mi = b.m;
    const double one = 1.0, zero = 0.0;
    dtrsm_(&r, &lo, &tr, &nu, &eight, &k, &one, b.L, &mi, xs, &eight);
    if (below > 0) {
      dgemm_(&nt, &tr, &eight, &below, &k, &one, xs, &eight, b.L + b.k, &mi, &zero, tmp, &eight);
      for (int i = 0; i < below; ++i) {
        double* xr = x8 + static_cast<int64_t>(b.rows[b.k + i]) * kLanes;
        Lane8 v = Lane8::load(xr);
        v.sub(Lane8::load(tmp + static_cast<int64_t>(i) * kLanes));
        v.store(xr);
      }
    }
    return;
  }
  for (int j = 0; j < b.k; ++j) {
    const double* Lj = b.L + j * m;
    Lane8 xj = Lane8::load(xs + j * kLanes);
    xj.scale(1.0 / Lj[j]);
    xj.store(xs + j * kLanes);
    for (int i = j + 1; i < b.k; ++i) {
      Lane8 xi = Lane8::load(xs + i * kLanes);
      xi.fnma(Lj[i], xj);
      xi.store(xs + i * kLanes);
    }
  }
  for (int i = 0; i < below; ++i) {
    Lane8 acc = Lane8::zero();
    for (int j = 0; j < b.k; ++j) acc.fma(b.L[j * m + b.k + i], Lane8::load(xs + j * kLanes));
    double* xr = x8 + static_cast<int64_t>(b.rows[b.k + i]) * kLanes;
    Lane8 v = Lane8::load(xr);
    v.sub(acc);
    v.store(xr);
  }
  (void)tmp;
}

void backward_supernode8(const NumericFactor& F, int32_t s, double* x8, double* tmp) {
  const SupernodeBlock b = supernode_block(F, s);
  double* xs = x8 + static_cast<int64_t>(b.f) * kLanes;
  const int64_t m = b.m;
  const int below = b.m - b.k;
  for (int i = 0; i < below; ++i)
    Lane8::load(x8 + static_cast<int64_t>(b.rows[b.k + i]) * kLanes).store(tmp + static_cast<int64_t>(i) * kLanes);
  if (b.k >= kBlasCols) {
    const char r = 'R', lo = 'L', nt = 'N', nu = 'N';
    const int eight = kLanes, k = b.k, mi = b.m;
    const double one = 1.0, mone = -1.0;
    if (below > 0) dgemm_(&nt, &nt, &eight, &k, &below, &mone, tmp, &eight, b.L + b.k, &mi, &one, xs, &eight);
    dtrsm_(&r, &lo, &nt, &nu, &eight, &k, &one, b.L, &mi, xs, &eight);
    return;
  }
  for (int j = b.k - 1; j >= 0; --j) {
    const double* Lj = b.L + j * m;
    Lane8 acc = Lane8::load(xs + j * kLanes);
    for (int i = 0; i < below; ++i) acc.fnma(Lj[b.k + i], Lane8::load(tmp + static_cast<int64_t>(i) * kLanes));
    for (int i = j + 1; i < b.k; ++i) acc.fnma(Lj[i], Lane8::load(xs + i * kLanes));
    acc.scale(1.0 / Lj[j]);
    acc.store(xs + j * kLanes);
  }
}

void forward_full(const NumericFactor& F, double* x, double* tmp) {
  for (int32_t s = 0; s < F.symbolic->ns; ++s) forward_supernode(F, s, x, tmp);
}
void backward_full(const NumericFactor& F, double* x, double* tmp) {
  for (int32_t s = F.symbolic->ns - 1; s >= 0; --s) backward_supernode(F, s, x, tmp);
}
void forward_full8(const NumericFactor& F, double* x8, double* tmp) {
  for (int32_t s = 0; s < F.symbolic->ns; ++s) forward_supernode8(F, s, x8, tmp);
}
void backward_full8(const NumericFactor& F, double* x8, double* tmp) {
  for (int32_t s = F.symbolic->ns - 1; s >= 0; --s) backward_supernode8(F, s, x8, tmp);
}

size_t solve_work_size(const NumericFactor& F, int lanes) {
  return static_cast<size_t>(F.n() + F.symbolic->max_super_rows) * static_cast<size_t>(lanes);
}

void solve(const NumericFactor& F, std::span<double> b, std::span<double> work) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "solve: empty factor");
  const int32_t n = F.n();
  if (static_cast<int64_t>(b.size()) != n)
    fail(ErrorCode::BadUsage, "solve: right-hand side has " + std::to_string(b.size()) + " entries, expected " + std::to_string(n));
  HostVector<double> own;
  if (work.size() < solve_work_size(F, 1)) { own.resize(solve_work_size(F, 1)); work = own; }
  double* x = work.data();
  double* tmp = x + n;
  const int32_t* perm = F.symbolic->perm.data();
  blas::SingleThreaded single;
  for (int32_t k = 0; k < n; ++k) x[k] = b[perm[k]];
  forward_full(F, x, tmp);
  backward_full(F, x, tmp);
  for (int32_t k = 0; k < n; ++k) b[perm[k]] = x[k];
}

void solve8(const NumericFactor& F, std::span<double> b8, std::span<double> work) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "solve8: empty factor");
  const int32_t n = F.n();
  if (static_cast<int64_t>(b8.size()) != static_cast<int64_t>(n) * kLanes)
    fail(ErrorCode::BadUsage, "solve8: right-hand side has " + std::to_string(b8.size()) + " entries, expected 8 x " + std::to_string(n));
  HostVector<double> own;
  if (work.size() < solve_work_size(F, kLanes)) { own.resize(solve_work_size(F, kLanes)); work = own; }
  double* x = work.data();
  double* tmp = x + static_cast<int64_t>(n) * kLanes;
  const int32_t* perm = F.symbolic->perm.data();
  blas::SingleThreaded single;
  for (int32_t k = 0; k < n; ++k) Lane8::load(b8.data() + static_cast<int64_t>(perm[k]) * kLanes).store(x + static_cast<int64_t>(k) * kLanes);
  forward_full8(F, x, tmp);
  backward_full8(F, x, tmp);
  for (int32_t k = 0; k < n; ++k) Lane8::load(x + static_cast<int64_t>(k) * kLanes).store(b8.data() + static_cast<int64_t>(perm[k]) * kLanes);
}

}  // namespace locus
