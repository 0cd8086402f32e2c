// Pairwise heat exchange (pipelines/include/locus/pipelines/heat/heat_exchange.hpp; thesis §4.6).
#include "locus/pipelines/heat/heat_exchange.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "locus/core/enum_names.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void check_set(std::span<const int32_t> ids, int32_t n, const char* what) {
  if (ids.empty()) fail(ErrorCode::BadUsage, std::string("heat exchange: no ") + what + " given");
  for (size_t k = 0; k < ids.size(); ++k)
    if (ids[k] < 0 || ids[k] >= n)
      fail(ErrorCode::BadUsage, std::string("heat exchange: ") + what + " entry " + std::to_string(k) + " is vertex " +
                                    std::to_string(ids[k]) + ", outside 0.." + std::to_string(n - 1));
}

}  // namespace

constexpr EnumNames<HeatExchangeMethod, 3> kHeatExchangeMethods{
    {{HeatExchangeMethod::Subset, "subset"}, {HeatExchangeMethod::Union, "union"}, {HeatExchangeMethod::Full, "full"}}};

HeatExchangeMethod parse_heat_exchange_method(const std::string& name) {
  return parse_enum_name(name, kHeatExchangeMethods, "heat exchange method");
}

const char* heat_exchange_method_name(HeatExchangeMethod m) { return enum_name(m, kHeatExchangeMethods); }

void heat_exchange(const NumericFactor& F, std::span<const int32_t> sources, std::span<const int32_t> targets,
                   HeatExchangeMethod method, std::span<double> out, HeatWorkspace& ws, HeatExchangeStats* stats) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "heat exchange: empty factor");
  const int32_t n = F.n();
  check_set(sources, n, "sources");
  check_set(targets, n, "targets");
  if (out.size() != targets.size())
    fail(ErrorCode::BadUsage, "heat exchange: output has " + std::to_string(out.size()) + " entries for " +
                                  std::to_string(targets.size()) + " targets");
  HeatExchangeStats st;
  auto t0 = std::chrono::steady_clock::now();
  if (method == HeatExchangeMethod::Full) {
    ws.dense.assign(static_cast<size_t>(n), 0.0);
    if (ws.work.size() < solve_work_size(F, 1)) ws.work.resize(solve_work_size(F, 1));
    for (int32_t s : sources) ws.dense[s] += 1.0;
    solve(F, ws.dense, ws.work);
    for (size_t k = 0; k < targets.size(); ++k) out[k] = ws.dense[targets[k]];
    st.solve_s = seconds_since(t0);
    st.forward_columns = st.backward_columns = n;
  } else if (method == HeatExchangeMethod::Subset) {
    const SolvePlan plan = plan_subset_solve(*F.symbolic, sources, targets);
    st.plan_s = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<double> ones(sources.size(), 1.0);
    solve_planned(F, plan, ones, out, ws.sparse);
    st.solve_s = seconds_since(t0);
    st.forward_columns = plan.forward_columns;
    st.backward_columns = plan.backward_columns;
  } else {
    // One subtree for both passes: support and wanted are S ∪ T (targets enter
    // the right-hand side with value 0, which adds nothing).
    std::vector<int32_t> both(sources.begin(), sources.end());
    both.insert(both.end(), targets.begin(), targets.end());
    const SolvePlan plan = plan_subset_solve(*F.symbolic, both, both);
    st.plan_s = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    std::vector<double> rhs(both.size(), 0.0), x(both.size());
    std::fill(rhs.begin(), rhs.begin() + static_cast<std::ptrdiff_t>(sources.size()), 1.0);
    solve_planned(F, plan, rhs, x, ws.sparse);
    for (size_t k = 0; k < targets.size(); ++k) out[k] = x[sources.size() + k];
    st.solve_s = seconds_since(t0);
    st.forward_columns = plan.forward_columns;
    st.backward_columns = plan.backward_columns;
  }
  if (stats) *stats = st;
}

}  // namespace locus
