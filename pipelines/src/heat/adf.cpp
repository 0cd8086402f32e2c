// Auto-diffusion function and heat kernel signature (pipelines/include/locus/pipelines/heat/adf.hpp; thesis §4.6, eq. 6.3).
#include "locus/pipelines/heat/adf.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "locus/core/enum_names.hpp"
#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/selected_inversion.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void check_vertex(const NumericFactor& F, int32_t v) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "auto-diffusion: empty factor");
  if (v < 0 || v >= F.n())
    fail(ErrorCode::BadUsage, "auto-diffusion: vertex " + std::to_string(v) + " is outside 0.." + std::to_string(F.n() - 1));
}

void size_sparse(const SymbolicFactor& S, SolveWorkspace& ws) {
  if (ws.x.size() < static_cast<size_t>(S.n)) ws.x.assign(static_cast<size_t>(S.n), 0.0);
  if (ws.tmp.size() < static_cast<size_t>(S.max_super_rows)) ws.tmp.resize(static_cast<size_t>(S.max_super_rows));
}

// y = L^{-1} e_c along the etree path of column c, then ||y||^2, leaving ws.x zero.
// Every nonzero of y lies in a column of a path supernode (the rows of a
// supernode are its ancestors' columns), so summing and clearing those suffices.
double path_norm2(const NumericFactor& F, int32_t c, SolveWorkspace& ws) {
  const SymbolicFactor& S = *F.symbolic;
  double* x = ws.x.data();
  double* tmp = ws.tmp.data();
  x[c] = 1.0;
  for (int32_t s = S.col_to_super[c]; s >= 0; s = S.super_parent[s]) forward_supernode(F, s, x, tmp);
  double sum = 0.0;
  for (int32_t s = S.col_to_super[c]; s >= 0; s = S.super_parent[s])
    for (int32_t j = S.super_first_col[s]; j < S.super_first_col[s + 1]; ++j) {
      sum += x[j] * x[j];
      x[j] = 0.0;
    }
  return sum;
}

void check_out(std::span<const int32_t> vertices, int32_t n, size_t per_vertex, std::span<double> out) {
  const size_t count = vertices.empty() ? static_cast<size_t>(n) : vertices.size();
  if (out.size() != count * per_vertex)
    fail(ErrorCode::BadUsage, "auto-diffusion: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(count * per_vertex));
  for (size_t k = 0; k < vertices.size(); ++k)
    if (vertices[k] < 0 || vertices[k] >= n)
      fail(ErrorCode::BadUsage, "auto-diffusion: vertex entry " + std::to_string(k) + " is " +
                                    std::to_string(vertices[k]) + ", outside 0.." + std::to_string(n - 1));
}

// Runs body(v, k, ws) for every queried vertex in parallel, per-thread workspaces.
template <class Body>
void for_each_vertex(int32_t n, std::span<const int32_t> vertices, const RunContext& ctx, const char* phase,
                     const Body& body) {
  const size_t count = vertices.empty() ? static_cast<size_t>(n) : vertices.size();
  tbb::enumerable_thread_specific<HeatWorkspace> scratch;
  std::atomic<size_t> done{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 64), [&](const tbb::blocked_range<size_t>& r) {
    ctx.check_cancel();
    HeatWorkspace& ws = scratch.local();
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const int32_t v = vertices.empty() ? static_cast<int32_t>(k) : vertices[k];
      body(v, k, ws);
    }
    const size_t d = done.fetch_add(r.size()) + r.size();
    ctx.report(static_cast<double>(d) / static_cast<double>(count), phase);
  });
}

}  // namespace

HeatFactors factor_heat_operators(const Mesh& m, std::span<const double> t, const RunContext& ctx,
                                  const OrderingOptions& ordering) {
  if (t.empty()) fail(ErrorCode::BadUsage, "heat operators: no diffusion time given");
  for (size_t k = 0; k < t.size(); ++k)
    if (!(std::isfinite(t[k]) && t[k] > 0))
      fail(ErrorCode::BadUsage, "heat operators: diffusion time " + std::to_string(k) + " is " + std::to_string(t[k]) +
                                    ", must be finite and > 0");
  HeatFactors H;
  H.t.assign(t.begin(), t.end());
  auto t0 = std::chrono::steady_clock::now();
  std::vector<CscMatrix> A;
  A.reserve(t.size());
  for (double tk : t) A.push_back(heat_operator(m, tk));
  H.operator_s = seconds_since(t0);
  ctx.check_cancel();
  // The pattern (diagonal + edges) does not depend on t: order and analyze once.
  t0 = std::chrono::steady_clock::now();
  const Ordering ord = order_matrix(A[0], ordering);
  H.order_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  H.symbolic = analyze(A[0], ord);
  H.analyze_s = seconds_since(t0);
  for (const CscMatrix& Ak : A) {
    ctx.check_cancel();
    t0 = std::chrono::steady_clock::now();
    H.factors.push_back(factorize(H.symbolic, Ak, ctx));
    H.numeric_s += seconds_since(t0);
  }
  return H;
}

constexpr EnumNames<AdfMethod, 3> kAdfMethods{
    {{AdfMethod::Subset, "subset"}, {AdfMethod::Selinv, "selinv"}, {AdfMethod::Full, "full"}}};

AdfMethod parse_adf_method(const std::string& name) {
  return parse_enum_name(name, kAdfMethods, "auto-diffusion method");
}

const char* adf_method_name(AdfMethod m) { return enum_name(m, kAdfMethods); }

double inverse_diagonal_entry(const NumericFactor& F, int32_t v, HeatWorkspace& ws) {
  check_vertex(F, v);
  size_sparse(*F.symbolic, ws.sparse);
  blas::SingleThreaded single;
  return path_norm2(F, F.symbolic->iperm[v], ws.sparse);
}

void inverse_diagonal_entries(std::span<const NumericFactor> factors, int32_t v, std::span<double> out,
                              HeatWorkspace& ws) {
  if (out.size() != factors.size())
    fail(ErrorCode::BadUsage, "auto-diffusion: " + std::to_string(out.size()) + " outputs for " +
                                  std::to_string(factors.size()) + " factors");
  if (factors.empty()) return;
  check_vertex(factors[0], v);
  for (const NumericFactor& F : factors)
    if (F.symbolic != factors[0].symbolic)
      fail(ErrorCode::BadUsage, "auto-diffusion: the factors do not share one symbolic factor");
  size_sparse(*factors[0].symbolic, ws.sparse);
  blas::SingleThreaded single;
  const int32_t c = factors[0].symbolic->iperm[v];
  for (size_t k = 0; k < factors.size(); ++k) out[k] = path_norm2(factors[k], c, ws.sparse);
}

double inverse_diagonal_entry_full(const NumericFactor& F, int32_t v, HeatWorkspace& ws) {
  check_vertex(F, v);
  const size_t n = static_cast<size_t>(F.n());
  ws.dense.assign(n, 0.0);
  if (ws.work.size() < solve_work_size(F, 1)) ws.work.resize(solve_work_size(F, 1));
  ws.dense[v] = 1.0;
  solve(F, ws.dense, ws.work);
  return ws.dense[v];
}

void heat_kernel_signature(const HeatFactors& H, std::span<const int32_t> vertices, AdfMethod method,
                           std::span<double> out, const RunContext& ctx) {
  if (H.factors.empty() || H.factors.size() != H.t.size())
    fail(ErrorCode::BadUsage, "heat kernel signature: no heat factors (factor_heat_operators)");
  const size_t nt = H.factors.size();
  const int32_t n = H.factors[0].n();
  check_out(vertices, n, nt, out);
  std::span<const NumericFactor> factors(H.factors);
  if (method == AdfMethod::Selinv) {
    // One selected inversion per t yields every vertex; pick the queried ones.
    for (size_t j = 0; j < nt; ++j) {
      ctx.check_cancel();
      const std::vector<double> d = inverse_diagonal(selected_inversion(factors[j], ctx));
      const size_t count = vertices.empty() ? static_cast<size_t>(n) : vertices.size();
      for (size_t k = 0; k < count; ++k) out[k * nt + j] = d[vertices.empty() ? k : static_cast<size_t>(vertices[k])];
      ctx.report(static_cast<double>(j + 1) / static_cast<double>(nt), "heat kernel signature");
    }
    return;
  }
  for_each_vertex(n, vertices, ctx, "heat kernel signature", [&](int32_t v, size_t k, HeatWorkspace& ws) {
    std::span<double> o = out.subspan(k * nt, nt);
    if (method == AdfMethod::Subset) {
      inverse_diagonal_entries(factors, v, o, ws);
    } else {
      for (size_t j = 0; j < nt; ++j) o[j] = inverse_diagonal_entry_full(factors[j], v, ws);
    }
  });
}

void auto_diffusion(const NumericFactor& F, std::span<const int32_t> vertices, AdfMethod method, std::span<double> out,
                    const RunContext& ctx) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "auto-diffusion: empty factor");
  check_out(vertices, F.n(), 1, out);
  if (method == AdfMethod::Selinv) {
    const std::vector<double> d = inverse_diagonal(selected_inversion(F, ctx));
    if (vertices.empty()) std::copy(d.begin(), d.end(), out.begin());
    else for (size_t k = 0; k < vertices.size(); ++k) out[k] = d[vertices[k]];
    return;
  }
  for_each_vertex(F.n(), vertices, ctx, "auto-diffusion", [&](int32_t v, size_t k, HeatWorkspace& ws) {
    out[k] = method == AdfMethod::Subset ? inverse_diagonal_entry(F, v, ws) : inverse_diagonal_entry_full(F, v, ws);
  });
}

}  // namespace locus
