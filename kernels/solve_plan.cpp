// Reach and ancestor sets of the supernodal etree (kernels/solve_plan.hpp).
// Marking uses a small hash-free trick: walk parents until an already-visited
// supernode, so each supernode of the result is visited once; then sort.
// Approximate plans mark kept columns instead of sorting them (only their
// supernodes are sorted) and derive the pruned forward list in one downward walk.
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

// Supernodes on the paths from the given vertices to the root, ascending, into
// `out`; `seen` is all zero on entry and on exit.
void ancestors_of(const SymbolicFactor& S, std::span<const int32_t> ids, std::vector<uint8_t>& seen,
                  std::vector<int32_t>& out) {
  out.clear();
  for (int32_t v : ids)
    for (int32_t s = S.col_to_super[S.iperm[v]]; s >= 0 && !seen[s]; s = S.super_parent[s]) {
      seen[s] = 1;
      out.push_back(s);
    }
  for (int32_t s : out) seen[s] = 0;
  std::sort(out.begin(), out.end());
}

int64_t columns_of(const SymbolicFactor& S, const std::vector<int32_t>& supers) {
  int64_t c = 0;
  for (int32_t s : supers) c += S.ncols(s);
  return c;
}

void base_plan(const SymbolicFactor& S, std::span<const int32_t> rhs, std::span<const int32_t> out, SolvePlan& p,
               PlanWorkspace& ws) {
  check_ids(S, rhs, "right-hand side support");
  check_ids(S, out, "output set");
  if (ws.seen.size() != static_cast<size_t>(S.ns)) ws.seen.assign(static_cast<size_t>(S.ns), 0);
  p.n = S.n;
  p.approximate = false;
  p.kept_cols.clear();
  p.forward_pruned.clear();
  p.rhs.assign(rhs.begin(), rhs.end());
  p.outputs.assign(out.begin(), out.end());
  ancestors_of(S, rhs, ws.seen, p.forward);
  p.forward_columns = columns_of(S, p.forward);
}

// touched = forward ∪ backward (backward is descending), ascending.
void finish(const SymbolicFactor& S, SolvePlan& p) {
  p.backward_columns = columns_of(S, p.backward);
  p.touched.clear();
  auto f = p.forward.begin();
  auto b = p.backward.rbegin();
  while (f != p.forward.end() || b != p.backward.rend()) {
    if (b == p.backward.rend() || (f != p.forward.end() && *f < *b)) {
      p.touched.push_back(*f++);
    } else {
      if (f != p.forward.end() && *f == *b) ++f;
      p.touched.push_back(*b++);
    }
  }
}

}  // namespace

void plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support, std::span<const int32_t> wanted,
                       SolvePlan& p, PlanWorkspace& ws) {
  base_plan(S, rhs_support, wanted, p, ws);
  ancestors_of(S, wanted, ws.seen, p.backward);
  std::reverse(p.backward.begin(), p.backward.end());
  finish(S, p);
}

void plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support, std::span<const int32_t> kept,
                          SolvePlan& p, PlanWorkspace& ws) {
  base_plan(S, rhs_support, kept, p, ws);
  p.approximate = true;
  if (ws.col_seen.size() != static_cast<size_t>(S.n)) ws.col_seen.assign(static_cast<size_t>(S.n), 0);
  // Kept columns and their supernodes by marks; only the (fewer) supernodes are
  // sorted, then each one's columns are read in order: kept_cols comes out
  // ascending without sorting the columns (CVT batches keep thousands).
  p.backward.clear();
  for (int32_t v : kept) {
    const int32_t c = S.iperm[v];
    if (ws.col_seen[c]) continue;
    ws.col_seen[c] = 1;
    const int32_t s = S.col_to_super[c];
    if (!ws.seen[s]) {
      ws.seen[s] = 1;
      p.backward.push_back(s);
    }
  }
  std::sort(p.backward.begin(), p.backward.end());
  p.kept_cols.clear();
  for (int32_t s : p.backward)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c)
      if (ws.col_seen[c]) {
        p.kept_cols.push_back(c);
        ws.col_seen[c] = 0;
      }
  // Pruned forward: walking the reach downwards (parents have larger ids), a
  // supernode is needed when it is kept (mark 1) or its parent is needed (mark 2);
  // the reach is closed under parents, so the parent's mark is already final.
  p.forward_pruned.clear();
  for (auto it = p.forward.rbegin(); it != p.forward.rend(); ++it) {
    const int32_t s = *it, par = S.super_parent[s];
    if ((ws.seen[s] & 1) || (par >= 0 && (ws.seen[par] & 2))) {
      ws.seen[s] |= 2;
      p.forward_pruned.push_back(s);
    }
  }
  std::reverse(p.forward_pruned.begin(), p.forward_pruned.end());
  for (int32_t s : p.forward) ws.seen[s] = 0;
  for (int32_t s : p.backward) ws.seen[s] = 0;
  std::reverse(p.backward.begin(), p.backward.end());
  finish(S, p);
}

SolvePlan plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                            std::span<const int32_t> wanted) {
  SolvePlan p;
  PlanWorkspace ws;
  plan_subset_solve(S, rhs_support, wanted, p, ws);
  return p;
}

SolvePlan plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                               std::span<const int32_t> kept) {
  SolvePlan p;
  PlanWorkspace ws;
  plan_selective_solve(S, rhs_support, kept, p, ws);
  return p;
}

}  // namespace locus
