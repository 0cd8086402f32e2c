// Factors from and to a factor cache file (engine/include/locus/engine/factor_store.hpp).
#include "locus/engine/factor_store.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "locus/core/release_free_memory.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/io/factor_cache.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/assembly_map.hpp"

namespace locus {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string operator_label(const std::string& kind, double t) {
  return t != 0 ? kind + " (t = " + format_number(t) + ")" : kind;
}

std::string operator_list(const std::vector<std::string>& kinds, const std::vector<double>& t) {
  std::string s;
  for (size_t k = 0; k < kinds.size(); ++k) s += (k ? ", " : "") + operator_label(kinds[k], t[k]);
  return s;
}

Factors load(const FactorCacheFiles& fc, const Mesh& m, std::span<const FactorRequest> ops, const RunContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  const CscMatrix& A0 = *ops[0].A;
  // The loaded factor lives in memory whole: its file size is what it costs.
  std::error_code size_ec;
  const uintmax_t bytes = std::filesystem::file_size(fc.load, size_ec);
  if (!size_ec && bytes > memory_limit_bytes(ctx))
    fail(ErrorCode::ResourceLimit, fc.load + ": loading it needs " + format_number(bytes / 1073741824.0) +
                                       " GiB, more than the memory limit of " +
                                       format_number(memory_limit_bytes(ctx) / 1073741824.0) +
                                       " GiB (raise it with --max-memory)");
  LoadedFactors L = load_factors(fc.load, mesh_content_hash(m));
  std::vector<std::string> want_kinds;
  std::vector<double> want_t;
  for (const FactorRequest& r : ops) {
    want_kinds.push_back(r.kind);
    want_t.push_back(r.t);
  }
  bool same = L.factors.size() == ops.size();
  for (size_t k = 0; same && k < ops.size(); ++k)
    same = L.operator_kinds[k] == ops[k].kind &&
           std::abs(L.t[k] - ops[k].t) <= 1e-12 * std::max(std::abs(L.t[k]), std::abs(ops[k].t));
  if (!same)
    fail(ErrorCode::BadInput, fc.load + ": holds factors of " + operator_list(L.operator_kinds, L.t) +
                                  ", but this command needs " + operator_list(want_kinds, want_t) +
                                  " (save it again with --save and these options)");
  const SymbolicFactor& S = *L.factors[0].symbolic;
  if (S.n != A0.ncols || S.a_nnz != A0.nnz() || S.a_pattern_hash != pattern_hash(A0))
    fail(ErrorCode::BadInput, fc.load + ": the saved factor is of another matrix pattern (" + std::to_string(S.n) +
                                  " columns, " + std::to_string(S.a_nnz) + " entries) than this operator (" +
                                  std::to_string(A0.ncols) + " columns, " + std::to_string(A0.nnz()) + " entries)");
  Factors F;
  F.symbolic = L.factors[0].symbolic;
  F.factors = std::move(L.factors);
  F.loaded = true;
  F.load_s = seconds_since(t0);
  ctx.note("loaded " + std::to_string(F.factors.size()) + " factor(s) from " + fc.load + " in " +
           format_number(F.load_s) + " s");
  return F;
}

}  // namespace

void check_factor_cache_files(const FactorCacheFiles& fc) {
  if (!fc.save.empty() && !fc.load.empty())
    fail(ErrorCode::BadUsage, "--save and --load exclude each other (load " + fc.load + " or save " + fc.save + ")");
}

namespace {

// Both paths build the symbolic factor as a mutable object (analyze, the cache
// reader) and share it only with the returned factors, so it may be changed here.
void release_assembly_of(Factors& F) {
  if (F.symbolic) release_assembly_map(*std::const_pointer_cast<SymbolicFactor>(F.symbolic));
}

Factors factor_or_load_all(const FactorCacheFiles& fc, const Mesh& m, std::span<const FactorRequest> ops,
                           const RunContext& ctx) {
  check_factor_cache_files(fc);
  if (ops.empty() || !ops[0].A) fail(ErrorCode::Internal, "factor_or_load: no operator");
  if (!fc.load.empty()) return load(fc, m, ops, ctx);
  const CscMatrix& A0 = *ops[0].A;
  for (const FactorRequest& r : ops)
    if (!r.A || r.A->ncols != A0.ncols || r.A->nnz() != A0.nnz())
      fail(ErrorCode::Internal, "factor_or_load: the operators do not share one pattern");
  Factors F;
  auto t0 = std::chrono::steady_clock::now();
  const Ordering ord = order_matrix(A0, {}, ctx);
  F.order_s = seconds_since(t0);
  ctx.check_cancel();
  t0 = std::chrono::steady_clock::now();
  F.symbolic = analyze(A0, ord);
  F.analyze_s = seconds_since(t0);
  // What the ordering, the analysis and the caller's checks freed stays
  // resident in the heap beside the factor otherwise (~40 MB at 416k vertices).
  release_free_memory();
  for (const FactorRequest& r : ops) {
    ctx.check_cancel();
    t0 = std::chrono::steady_clock::now();
    F.factors.push_back(factorize(F.symbolic, *r.A, ctx));
    F.numeric_s += seconds_since(t0);
  }
  if (!fc.save.empty()) {
    ctx.check_cancel();
    t0 = std::chrono::steady_clock::now();
    std::vector<FactorEntry> entries;
    for (size_t k = 0; k < ops.size(); ++k) entries.push_back({ops[k].kind, ops[k].t, &F.factors[k]});
    save_factors(fc.save, mesh_content_hash(m), entries);
    F.save_s = seconds_since(t0);
    ctx.note("saved " + std::to_string(entries.size()) + " factor(s) to " + fc.save);
  }
  return F;
}

}  // namespace

Factors factor_or_load(const FactorCacheFiles& fc, const Mesh& m, std::span<const FactorRequest> ops,
                       const RunContext& ctx, bool factor_once) {
  Factors F = factor_or_load_all(fc, m, ops, ctx);
  if (factor_once) release_assembly_of(F);
  return F;
}

}  // namespace locus
