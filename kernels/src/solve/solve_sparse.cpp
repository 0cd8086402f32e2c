// Plan-driven sparse solves (kernels/include/locus/kernels/solve/solve_sparse.hpp).
#include "locus/kernels/solve/solve_sparse.hpp"

#include <algorithm>
#include <string>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/simd/lane8.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "supernode_block.hpp"

namespace locus {

namespace {

void prepare(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
             SolveWorkspace& ws, int lanes) {
  if (!F.symbolic || plan.n != F.n()) fail(ErrorCode::BadUsage, "solve plan was made for another factor");
  if (rhs.size() != plan.rhs.size() * lanes)
    fail(ErrorCode::BadUsage, "planned solve: " + std::to_string(rhs.size()) + " right-hand side values for a support of " +
                                  std::to_string(plan.rhs.size()) + " x " + std::to_string(lanes));
  if (out.size() != plan.outputs.size() * lanes)
    fail(ErrorCode::BadUsage, "planned solve: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(plan.outputs.size()) + " x " + std::to_string(lanes));
  const size_t nx = static_cast<size_t>(F.n()) * lanes;
  if (ws.x.size() < nx) ws.x.assign(nx, 0.0);
  const size_t nt = static_cast<size_t>(F.symbolic->max_super_rows) * lanes;
  if (ws.tmp.size() < nt) ws.tmp.resize(nt);
  if (plan.approximate && ws.keep.size() < static_cast<size_t>(F.n())) ws.keep.assign(F.n(), 0);
}

// b is added (not assigned): repeated support entries sum, as in a sparse vector.
void scatter_rhs(const SymbolicFactor& S, const SolvePlan& plan, std::span<const double> rhs, double* x, int lanes) {
  for (size_t k = 0; k < plan.rhs.size(); ++k) {
    const int64_t c = S.iperm[plan.rhs[k]];
    for (int l = 0; l < lanes; ++l) x[c * lanes + l] += rhs[k * lanes + l];
  }
}

void zero_unkept_forward(const SymbolicFactor& S, const SolvePlan& plan, const uint8_t* keep, double* x, int lanes) {
  for (int32_t s : plan.forward)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c)
      if (!keep[c]) std::fill(x + static_cast<int64_t>(c) * lanes, x + static_cast<int64_t>(c + 1) * lanes, 0.0);
}

// Backward step of Algorithm 2 on one supernode: columns outside the kept set are zero.
void backward_masked(const NumericFactor& F, int32_t s, double* x, double* tmp, const uint8_t* keep) {
  const auto [f, k, m, rows, L] = supernode_block(F, s);
  const int below = m - k;
  for (int i = 0; i < below; ++i) tmp[i] = x[rows[k + i]];
  double* xs = x + f;
  for (int j = k - 1; j >= 0; --j) {
    if (!keep[f + j]) { xs[j] = 0.0; continue; }
    const double* Lj = L + static_cast<int64_t>(j) * m;
    double acc = xs[j];
    for (int i = 0; i < below; ++i) acc -= Lj[k + i] * tmp[i];
    for (int i = j + 1; i < k; ++i) acc -= Lj[i] * xs[i];
    xs[j] = acc / Lj[j];
  }
}

void backward_masked8(const NumericFactor& F, int32_t s, double* x8, double* tmp, const uint8_t* keep) {
  const auto [f, k, m, rows, L] = supernode_block(F, s);
  const int below = m - k;
  for (int i = 0; i < below; ++i)
    Lane8::load(x8 + static_cast<int64_t>(rows[k + i]) * kLanes).store(tmp + static_cast<int64_t>(i) * kLanes);
  double* xs = x8 + static_cast<int64_t>(f) * kLanes;
  for (int j = k - 1; j >= 0; --j) {
    if (!keep[f + j]) { Lane8::zero().store(xs + j * kLanes); continue; }
    const double* Lj = L + static_cast<int64_t>(j) * m;
    Lane8 acc = Lane8::load(xs + j * kLanes);
    for (int i = 0; i < below; ++i) acc.fnma(Lj[k + i], Lane8::load(tmp + static_cast<int64_t>(i) * kLanes));
    for (int i = j + 1; i < k; ++i) acc.fnma(Lj[i], Lane8::load(xs + i * kLanes));
    acc.scale(1.0 / Lj[j]);
    acc.store(xs + j * kLanes);
  }
}

template <int Lanes>
void run(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
         SolveWorkspace& ws) {
  prepare(F, plan, rhs, out, ws, Lanes);
  const SymbolicFactor& S = *F.symbolic;
  blas::SingleThreaded single;
  double* x = ws.x.data();
  double* tmp = ws.tmp.data();
  scatter_rhs(S, plan, rhs, x, Lanes);
  for (int32_t s : plan.forward) {
    if constexpr (Lanes == 1) forward_supernode(F, s, x, tmp);
    else forward_supernode8(F, s, x, tmp);
  }
  if (plan.approximate) {
    uint8_t* keep = ws.keep.data();
    for (int32_t c : plan.kept_cols) keep[c] = 1;
    zero_unkept_forward(S, plan, keep, x, Lanes);
    for (int32_t s : plan.backward) {
      if constexpr (Lanes == 1) backward_masked(F, s, x, tmp, keep);
      else backward_masked8(F, s, x, tmp, keep);
    }
    for (int32_t c : plan.kept_cols) keep[c] = 0;
  } else {
    for (int32_t s : plan.backward) {
      if constexpr (Lanes == 1) backward_supernode(F, s, x, tmp);
      else backward_supernode8(F, s, x, tmp);
    }
  }
  for (size_t k = 0; k < plan.outputs.size(); ++k) {
    const int64_t c = S.iperm[plan.outputs[k]];
    for (int l = 0; l < Lanes; ++l) out[k * Lanes + l] = x[c * Lanes + l];
  }
  clear_workspace(F, plan, ws, Lanes);
}

}  // namespace

void solve_planned(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
                   SolveWorkspace& ws) {
  run<1>(f, plan, rhs, out, ws);
}

void solve_planned8(const NumericFactor& f, const SolvePlan& plan, std::span<const double> rhs, std::span<double> out,
                    SolveWorkspace& ws) {
  run<kLanes>(f, plan, rhs, out, ws);
}

void forward_planned(const NumericFactor& F, const SolvePlan& plan, std::span<const double> rhs, SolveWorkspace& ws) {
  prepare(F, plan, rhs, std::span<double>(static_cast<double*>(nullptr), plan.outputs.size()), ws, 1);
  blas::SingleThreaded single;
  scatter_rhs(*F.symbolic, plan, rhs, ws.x.data(), 1);
  for (int32_t s : plan.forward) forward_supernode(F, s, ws.x.data(), ws.tmp.data());
}

void clear_workspace(const NumericFactor& F, const SolvePlan& plan, SolveWorkspace& ws, int lanes) {
  const SymbolicFactor& S = *F.symbolic;
  for (int32_t s : plan.touched)
    std::fill(ws.x.begin() + static_cast<int64_t>(S.super_first_col[s]) * lanes,
              ws.x.begin() + static_cast<int64_t>(S.super_first_col[s + 1]) * lanes, 0.0);
}

}  // namespace locus
