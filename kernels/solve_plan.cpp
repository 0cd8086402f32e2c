// Reach and ancestor sets of the supernodal etree (kernels/solve_plan.hpp).
// Marking uses a small hash-free trick: walk parents until an already-visited
// supernode, so each supernode of the result is visited once; then sort.
#include "kernels/solve_plan.hpp"

#include <algorithm>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

void check_ids(const SymbolicFactor& S, std::span<const int32_t> ids, const char* what) {
  for (size_t k = 0; k < ids.size(); ++k)
    if (ids[k] < 0 || ids[k] >= S.n)
      fail(ErrorCode::BadUsage, std::string(what) + " entry " + std::to_string(k) + " is vertex " + std::to_string(ids[k]) +
                                    ", outside 0.." + std::to_string(S.n - 1));
}

// Supernodes on the paths from the given vertices to the root, ascending.
std::vector<int32_t> ancestors_of(const SymbolicFactor& S, std::span<const int32_t> ids, std::vector<uint8_t>& seen) {
  std::vector<int32_t> out;
  for (int32_t v : ids)
    for (int32_t s = S.col_to_super[S.iperm[v]]; s >= 0 && !seen[s]; s = S.super_parent[s]) {
      seen[s] = 1;
      out.push_back(s);
    }
  for (int32_t s : out) seen[s] = 0;
  std::sort(out.begin(), out.end());
  return out;
}

int64_t columns_of(const SymbolicFactor& S, const std::vector<int32_t>& supers) {
  int64_t c = 0;
  for (int32_t s : supers) c += S.ncols(s);
  return c;
}

SolvePlan base_plan(const SymbolicFactor& S, std::span<const int32_t> rhs, std::span<const int32_t> out,
                    std::vector<uint8_t>& seen) {
  check_ids(S, rhs, "right-hand side support");
  check_ids(S, out, "output set");
  SolvePlan p;
  p.n = S.n;
  p.rhs.assign(rhs.begin(), rhs.end());
  p.outputs.assign(out.begin(), out.end());
  p.forward = ancestors_of(S, rhs, seen);
  p.forward_columns = columns_of(S, p.forward);
  return p;
}

void finish(const SymbolicFactor& S, SolvePlan& p) {
  p.backward_columns = columns_of(S, p.backward);
  std::vector<int32_t> bw(p.backward.rbegin(), p.backward.rend());
  p.touched.clear();
  std::set_union(p.forward.begin(), p.forward.end(), bw.begin(), bw.end(), std::back_inserter(p.touched));
}

}  // namespace

SolvePlan plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                            std::span<const int32_t> wanted) {
  std::vector<uint8_t> seen(S.ns, 0);
  SolvePlan p = base_plan(S, rhs_support, wanted, seen);
  p.backward = ancestors_of(S, wanted, seen);
  std::reverse(p.backward.begin(), p.backward.end());
  finish(S, p);
  return p;
}

SolvePlan plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                               std::span<const int32_t> kept) {
  std::vector<uint8_t> seen(S.ns, 0);
  SolvePlan p = base_plan(S, rhs_support, kept, seen);
  p.approximate = true;
  p.kept_cols.reserve(kept.size());
  for (int32_t v : kept) p.kept_cols.push_back(S.iperm[v]);
  std::sort(p.kept_cols.begin(), p.kept_cols.end());
  p.kept_cols.erase(std::unique(p.kept_cols.begin(), p.kept_cols.end()), p.kept_cols.end());
  for (int32_t c : p.kept_cols) {
    const int32_t s = S.col_to_super[c];
    if (p.backward.empty() || p.backward.back() != s) p.backward.push_back(s);
  }
  std::reverse(p.backward.begin(), p.backward.end());
  finish(S, p);
  return p;
}

}  // namespace locus
