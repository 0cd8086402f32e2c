// Reach and ancestor sets of the supernodal etree (kernels/include/locus/kernels/solve/solve_plan.hpp).
// Marking uses a small hash-free trick: walk parents until an already-visited
// supernode, so each supernode of the result is visited once; then sort (or,
// for large sets, read them off a bit set in ascending order: a log-map region
// of 200k vertices has ~50k supernodes, whose sort cost more than the walk).
// Approximate plans mark kept columns instead of sorting them (only their
// supernodes are sorted) and derive the pruned forward list in one downward walk.
#include "locus/kernels/solve/solve_plan.hpp"

#include <algorithm>
#include <string>

#include "locus/core/bit_set.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

void check_ids(const SymbolicFactor& S, std::span<const int32_t> ids, const char* what) {
  for (size_t k = 0; k < ids.size(); ++k)
    if (ids[k] < 0 || ids[k] >= S.n)
      fail(ErrorCode::BadUsage, std::string(what) + " entry " + std::to_string(k) + " is vertex " + std::to_string(ids[k]) +
                                    ", outside 0.." + std::to_string(S.n - 1));
}

// Ascending order of distinct supernode ids: a sort for small sets, a bit set
// scan (ns / 64 words) once the set is large enough for that to be cheaper.
void sort_supernodes(HostVector<int32_t>& ids, int32_t ns, HostVector<uint64_t>& bits) {
  const size_t words = bit_words(static_cast<size_t>(ns));
  if (ids.size() < 256 || ids.size() * 8 < words) {
    std::sort(ids.begin(), ids.end());
    return;
  }
  bits.assign(words, 0);
  for (int32_t s : ids) set_bit(bits, s);
  ids.clear();
  append_set_bits(bits, ids);
}

// Supernodes on the paths from the given vertices to the root, ascending, into
// `out`; `seen` is all zero on entry and on exit. With `vsuper` (vertex ->
// supernode) one lookup per vertex instead of two (iperm, then col_to_super).
void ancestors_of(const SymbolicFactor& S, std::span<const int32_t> ids, std::span<const int32_t> vsuper,
                  PlanWorkspace& ws, HostVector<int32_t>& out) {
  HostVector<uint8_t>& seen = ws.seen;
  out.clear();
  const bool direct = !vsuper.empty();
  for (int32_t v : ids)
    for (int32_t s = direct ? vsuper[v] : S.col_to_super[S.iperm[v]]; s >= 0 && !seen[s]; s = S.super_parent[s]) {
      seen[s] = 1;
      out.push_back(s);
    }
  for (int32_t s : out) seen[s] = 0;
  sort_supernodes(out, S.ns, ws.bits);
}

int64_t columns_of(const SymbolicFactor& S, const HostVector<int32_t>& supers) {
  int64_t c = 0;
  for (int32_t s : supers) c += S.ncols(s);
  return c;
}

// An exact plan's fields other than its supernode lists, for these ids.
void start_plan(const SymbolicFactor& S, std::span<const int32_t> rhs, std::span<const int32_t> out, SolvePlan& p) {
  p.n = S.n;
  p.approximate = false;
  p.kept_cols.clear();
  p.forward_pruned.clear();
  p.rhs.assign(rhs.begin(), rhs.end());
  p.outputs.assign(out.begin(), out.end());
}

bool is_prefix(std::span<const int32_t> a, const HostVector<int32_t>& b) {
  return a.size() <= b.size() && std::equal(a.begin(), a.end(), b.begin());
}

void base_plan(const SymbolicFactor& S, std::span<const int32_t> rhs, std::span<const int32_t> out, SolvePlan& p,
               PlanWorkspace& ws, std::span<const int32_t> vsuper = {}) {
  check_ids(S, rhs, "right-hand side support");
  check_ids(S, out, "output set");
  if (ws.seen.size() != static_cast<size_t>(S.ns)) ws.seen.assign(static_cast<size_t>(S.ns), 0);
  start_plan(S, rhs, out, p);
  ancestors_of(S, rhs, vsuper, ws, p.forward);
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

template <class Plan>
SolvePlan planned(Plan plan) {
  SolvePlan p;
  PlanWorkspace ws;
  plan(p, ws);
  return p;
}

}  // namespace

void plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support, std::span<const int32_t> wanted,
                       SolvePlan& p, PlanWorkspace& ws) {
  plan_subset_solve(S, {}, rhs_support, wanted, p, ws);
}

HostVector<int32_t> vertex_supernodes(const SymbolicFactor& S) {
  HostVector<int32_t> v(static_cast<size_t>(S.n));
  for (int32_t i = 0; i < S.n; ++i) v[i] = S.col_to_super[S.iperm[i]];
  return v;
}

void plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> vertex_super,
                       std::span<const int32_t> rhs_support, std::span<const int32_t> wanted, SolvePlan& p,
                       PlanWorkspace& ws) {
  if (!vertex_super.empty() && vertex_super.size() != static_cast<size_t>(S.n))
    fail(ErrorCode::BadUsage, "solve plan: vertex -> supernode table has " + std::to_string(vertex_super.size()) +
                                  " entries for " + std::to_string(S.n) + " vertices");
  base_plan(S, rhs_support, wanted, p, ws, vertex_super);
  ancestors_of(S, wanted, vertex_super, ws, p.backward);
  std::reverse(p.backward.begin(), p.backward.end());
  finish(S, p);
}

void plan_subset_solve_within(const SymbolicFactor& S, const SolvePlan& cover, std::span<const int32_t> rhs_support,
                              std::span<const int32_t> wanted, SolvePlan& p, PlanWorkspace& ws) {
  if (&cover == &p) fail(ErrorCode::BadUsage, "solve plan: the covering plan and the result must differ");
  if (cover.approximate || cover.n != S.n || !is_prefix(rhs_support, cover.outputs) ||
      !is_prefix(wanted, cover.outputs)) {
    plan_subset_solve(S, rhs_support, wanted, p, ws);
    return;
  }
  // (Both are prefixes of cover.outputs, which were range-checked when it was made.)
  start_plan(S, rhs_support, wanted, p);
  // cover.backward holds the ancestors of all of cover.outputs: the reach of
  // the support and a superset of the wanted vertices' ancestors (exact: the
  // extra supernodes feed no wanted entry).
  p.forward.assign(cover.backward.rbegin(), cover.backward.rend());
  p.forward_columns = cover.backward_columns;
  p.backward.assign(cover.backward.begin(), cover.backward.end());
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

// The one-shot forms: a plan with a workspace of its own.
SolvePlan plan_subset_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                            std::span<const int32_t> wanted) {
  return planned([&](SolvePlan& p, PlanWorkspace& ws) { plan_subset_solve(S, rhs_support, wanted, p, ws); });
}

SolvePlan plan_selective_solve(const SymbolicFactor& S, std::span<const int32_t> rhs_support,
                               std::span<const int32_t> kept) {
  return planned([&](SolvePlan& p, PlanWorkspace& ws) { plan_selective_solve(S, rhs_support, kept, p, ws); });
}

PlanTraffic plan_traffic(const SymbolicFactor& S, const SolvePlan& plan) {
  auto bytes = [&S](int32_t s) {
    if (s < 0 || s >= S.ns) fail(ErrorCode::BadUsage, "plan_traffic: supernode " + std::to_string(s) + " is not in the factor");
    return 8 * (S.super_value_ptr[s + 1] - S.super_value_ptr[s]) + 4 * static_cast<int64_t>(S.nrows(s));
  };
  PlanTraffic t;
  for (int32_t s : plan.forward) t.forward_bytes += bytes(s);
  for (int32_t s : plan.backward) t.backward_bytes += bytes(s);
  // Both lists are sorted (forward ascending, backward descending): merge-count the common ones.
  int64_t common = 0;
  auto f = plan.forward.begin();
  for (auto b = plan.backward.rbegin(); b != plan.backward.rend(); ++b) {
    while (f != plan.forward.end() && *f < *b) ++f;
    if (f != plan.forward.end() && *f == *b) common += bytes(*b);
  }
  t.distinct_bytes = t.read_bytes() - common;
  return t;
}

}  // namespace locus
