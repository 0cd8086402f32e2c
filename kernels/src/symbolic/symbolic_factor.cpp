// Symbolic analysis driver (kernels/include/locus/kernels/symbolic/symbolic_factor.hpp).
//
// Order of work: (1) etree of the ordered graph and its postorder; the
// final ordering is the given one composed with that postorder, which changes no fill
// but makes every subtree a contiguous range of columns; (2) column counts
// (Gilbert–Ng–Peyton); (3) relaxed supernodes; (4) supernode row structures,
// from the graph and the children's structures, in O(sum of supernode rows);
// (5) the A -> L assembly map, the left-looking update lists and workspace size.
// (1) reads the neighbours below each column, (2), (4) and (5) those above
// (all they use), which halves building the graphs. After (1) every subtree is
// a contiguous range, so (2) and (4) sweep disjoint subtrees as parallel
// oneTBB tasks and the nodes above them after (subtree_partition.hpp); (5) is
// parallel over supernodes. Every result is independent of the thread count
// (docs/ordering.md "Parallel symbolic analysis").
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/core/host_allocator.hpp"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <string>

#include "locus/kernels/symbolic/column_counts.hpp"
#include "locus/kernels/symbolic/etree.hpp"
#include "locus/kernels/symbolic/supernodes.hpp"
#include "locus/kernels/symbolic/assembly_map.hpp"
#include "locus/kernels/symbolic/permuted_graph.hpp"
#include "locus/kernels/symbolic/subtree_partition.hpp"
#include "locus/kernels/symbolic/supernode_rows.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/error.hpp"
#include "locus/view.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

// Below this many columns the analysis runs on the calling thread alone
// (~4 ms at 16k columns; see docs/ordering.md "Parallel symbolic analysis").
constexpr int32_t kParallelMinColumns = 16384;
// The scatters' counters (graphs, assembly map) cost chunks * n words; more
// chunks than ~4 only add counters to a memory-bound loop.
constexpr int kMaxGraphChunks = 4;

void check_lower(const CscMatrix& A) {
  if (A.nrows != A.ncols)
    fail(ErrorCode::BadUsage, "matrix is " + std::to_string(A.nrows) + " x " + std::to_string(A.ncols) + ", not square");
  const int32_t n = A.ncols;
  if (static_cast<int64_t>(A.colptr.size()) != static_cast<int64_t>(n) + 1 || A.colptr[0] != 0 ||
      static_cast<int64_t>(A.rowind.size()) != A.colptr[n] || static_cast<int64_t>(A.values.size()) != A.colptr[n])
    fail(ErrorCode::BadUsage, "matrix arrays are inconsistent (colptr/rowind/values sizes)");
  for (int32_t j = 0; j < n; ++j) {
    if (A.colptr[j + 1] < A.colptr[j]) fail(ErrorCode::BadUsage, "matrix colptr decreases at column " + std::to_string(j));
    int32_t prev = -1;
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (i < j || i >= n || i <= prev)
        fail(ErrorCode::BadUsage, "matrix is not lower-stored with sorted unique rows (column " + std::to_string(j) +
                                      ", row " + std::to_string(i) + ")");
      prev = i;
    }
  }
}

}  // namespace

uint64_t pattern_hash(const CscMatrix& A) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](uint64_t v) { h = (h ^ v) * 1099511628211ull; h ^= h >> 29; };
  mix(static_cast<uint64_t>(A.nrows));
  mix(static_cast<uint64_t>(A.ncols));
  for (int64_t v : A.colptr) mix(static_cast<uint64_t>(v));
  for (int32_t v : A.rowind) mix(static_cast<uint64_t>(v));
  return h;
}

int64_t SymbolicFactor::flops(int32_t s) const {
  // Column j of the supernode: r - j entries, each updating the r - j rows below it.
  const double r = nrows(s), c = ncols(s);
  double f = 0;
  for (int32_t j = 0; j < c; ++j) f += (r - j) * (r - j);
  return static_cast<int64_t>(f);
}

int64_t SymbolicFactor::flops() const {
  int64_t f = 0;
  for (int32_t s = 0; s < ns; ++s) f += flops(s);
  return f;
}

void compute_update_lists(SymbolicFactor& S) {
  const int32_t ns = S.ns;
  S.max_update_entries = 0;
  S.update_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    HostVector<int64_t> next;
    if (pass == 1) {
      for (int32_t s = 0; s < ns; ++s) S.update_ptr[s + 1] += S.update_ptr[s];
      S.update_from.resize(static_cast<size_t>(S.update_ptr[ns]));
      next.assign(S.update_ptr.begin(), S.update_ptr.end() - 1);
    }
    for (int32_t d = 0; d < ns; ++d) {
      cancel_point(d);
      const int64_t r0 = S.super_row_ptr[d], nr = S.nrows(d);
      int64_t t = S.ncols(d);
      while (t < nr) {
        const int32_t s = S.col_to_super[S.super_rows[r0 + t]];
        const int32_t send = S.super_first_col[s + 1];
        int64_t t2 = t;
        while (t2 < nr && S.super_rows[r0 + t2] < send) ++t2;
        if (pass == 0) {
          ++S.update_ptr[s + 1];
          S.max_update_entries = std::max(S.max_update_entries, (nr - t) * (t2 - t));
        } else {
          S.update_from[next[s]++] = d;
        }
        t = t2;
      }
    }
  }
}

namespace {

// complete_symbolic with S.a_pattern_hash already set if `hashed`; oneTBB
// tasks when chunks > 1 (the assembly map's chunk count).
void complete_symbolic_with(SymbolicFactor& S, const CscMatrix& A, bool hashed, int chunks) {
  const int32_t n = S.n, ns = S.ns;
  S.a_nnz = A.nnz();
  S.super_etree_height = tree_height(S.super_parent);
  if (static_cast<int32_t>(S.parent.size()) != n) {  // column etree from the supernodal structure
    S.parent.assign(n, -1);
    S.col_count.assign(n, 0);
    for (int32_t s = 0; s < ns; ++s) {
      const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
      for (int32_t c = f; c < l; ++c) {
        S.col_count[c] = S.nrows(s) - (c - f);
        if (c + 1 < l) S.parent[c] = c + 1;
        else if (S.nrows(s) > S.ncols(s)) S.parent[c] = S.super_rows[S.super_row_ptr[s] + S.ncols(s)];
      }
    }
    S.nnz_exact = 0;
    for (int32_t c : S.col_count) S.nnz_exact += c;
    S.etree_height = tree_height(S.parent);
  }
  S.max_super_rows = 0;
  S.max_update_entries = 0;
  S.super_value_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  S.nnz_L = 0;
  for (int32_t s = 0; s < ns; ++s) {
    const int64_t r = S.nrows(s), c = S.ncols(s);
    S.super_value_ptr[s + 1] = S.super_value_ptr[s] + r * c;
    S.nnz_L += r * c - c * (c - 1) / 2;
    S.max_super_rows = std::max<int32_t>(S.max_super_rows, static_cast<int32_t>(r));
  }

  // The pattern hash, the assembly map (itself parallel over supernodes) and
  // the update lists read the structure only and write disjoint fields.
  const auto hash = [&] {
    if (!hashed) S.a_pattern_hash = pattern_hash(A);
  };
  if (chunks <= 1) {
    hash();
    compute_update_lists(S);
    assembly_map(S, A, 1);
    return;
  }
  tbb::parallel_invoke(hash, [&] { compute_update_lists(S); }, [&] { assembly_map(S, A, chunks); });
}

}  // namespace

void complete_symbolic(SymbolicFactor& S, const CscMatrix& A) {
  if (A.ncols != S.n) fail(ErrorCode::BadUsage, "complete_symbolic: matrix size differs from the factor's");
  complete_symbolic_with(S, A, false, std::min(kMaxGraphChunks, tbb::this_task_arena::max_concurrency()));
}

void validate_symbolic(const SymbolicFactor& S, int64_t num_values) {
  auto bad = [](const std::string& what) { fail(ErrorCode::BadInput, "invalid factor structure: " + what); };
  const int32_t n = S.n, ns = S.ns;
  if (n < 0 || ns < 0 || ns > n || (n > 0 && ns == 0)) bad("sizes n/ns");
  if (static_cast<int32_t>(S.perm.size()) != n || static_cast<int32_t>(S.iperm.size()) != n) bad("permutation size");
  for (int32_t k = 0; k < n; ++k)
    if (S.perm[k] < 0 || S.perm[k] >= n || S.iperm[S.perm[k]] != k) bad("permutation at " + std::to_string(k));
  if (static_cast<int32_t>(S.super_first_col.size()) != ns + 1 || S.super_first_col[0] != 0 || S.super_first_col[ns] != n)
    bad("supernode column ranges");
  for (int32_t s = 0; s < ns; ++s)
    if (S.super_first_col[s + 1] <= S.super_first_col[s]) bad("empty supernode " + std::to_string(s));
  if (static_cast<int32_t>(S.col_to_super.size()) != n) bad("column map size");
  for (int32_t s = 0; s < ns; ++s)
    for (int32_t c = S.super_first_col[s]; c < S.super_first_col[s + 1]; ++c)
      if (S.col_to_super[c] != s) bad("column map at " + std::to_string(c));
  if (static_cast<int32_t>(S.super_parent.size()) != ns) bad("supernodal etree size");
  for (int32_t s = 0; s < ns; ++s)
    if (S.super_parent[s] != -1 && (S.super_parent[s] <= s || S.super_parent[s] >= ns)) bad("supernodal parent of " + std::to_string(s));
  if (static_cast<int32_t>(S.parent.size()) != n || static_cast<int32_t>(S.col_count.size()) != n) bad("column etree size");
  for (int32_t j = 0; j < n; ++j)
    if (S.parent[j] != -1 && (S.parent[j] <= j || S.parent[j] >= n)) bad("column parent of " + std::to_string(j));
  if (static_cast<int32_t>(S.super_row_ptr.size()) != ns + 1 || S.super_row_ptr[0] != 0 ||
      S.super_row_ptr[ns] != static_cast<int64_t>(S.super_rows.size()))
    bad("row pointers");
  for (int32_t s = 0; s < ns; ++s) {
    if (S.super_row_ptr[s + 1] - S.super_row_ptr[s] < S.ncols(s)) bad("rows of supernode " + std::to_string(s));
    const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
    for (int32_t t = 0; t < S.nrows(s); ++t) {
      if (t < S.ncols(s) ? rows[t] != S.super_first_col[s] + t : (rows[t] <= rows[t - 1] || rows[t] >= n))
        bad("row " + std::to_string(t) + " of supernode " + std::to_string(s));
    }
  }
  if (static_cast<int32_t>(S.super_value_ptr.size()) != ns + 1 || S.super_value_ptr[0] != 0) bad("value offsets");
  for (int32_t s = 0; s < ns; ++s)
    if (S.super_value_ptr[s + 1] - S.super_value_ptr[s] != static_cast<int64_t>(S.nrows(s)) * S.ncols(s)) bad("value offsets of " + std::to_string(s));
  if (num_values >= 0 && S.super_value_ptr[ns] != num_values) bad("number of values");
  // Closure: every row of d at or after a supernode s it reaches is a row of s
  // (left-looking updates and refactorization index through it).
  for (int32_t d = 0; d < ns; ++d) {
    const int32_t* rd = S.super_rows.data() + S.super_row_ptr[d];
    const int32_t nr = S.nrows(d);
    for (int32_t t = S.ncols(d); t < nr;) {
      const int32_t s = S.col_to_super[rd[t]];
      const int32_t* rs = S.super_rows.data() + S.super_row_ptr[s];
      int32_t q = 0;
      for (int32_t u = t; u < nr; ++u) {
        while (q < S.nrows(s) && rs[q] < rd[u]) ++q;
        if (q == S.nrows(s) || rs[q] != rd[u]) bad("structure not closed at supernodes " + std::to_string(d) + ", " + std::to_string(s));
      }
      while (t < nr && S.col_to_super[rd[t]] == s) ++t;
    }
  }
  if (static_cast<int64_t>(S.a_super_ptr.size()) != ns + 1 || S.a_super_ptr[0] != 0 || S.a_super_ptr[ns] != S.a_nnz ||
      static_cast<int64_t>(S.a_src.size()) != S.a_nnz || static_cast<int64_t>(S.a_dst.size()) != S.a_nnz)
    bad("assembly map sizes");
  for (int32_t s = 0; s < ns; ++s) {
    if (S.a_super_ptr[s + 1] < S.a_super_ptr[s]) bad("assembly map pointers");
    for (int64_t k = S.a_super_ptr[s]; k < S.a_super_ptr[s + 1]; ++k)
      if (S.a_src[k] < 0 || S.a_src[k] >= S.a_nnz || S.a_dst[k] < S.super_value_ptr[s] || S.a_dst[k] >= S.super_value_ptr[s + 1])
        bad("assembly map entry " + std::to_string(k));
  }
}

namespace {

// Everything after the checks, in the arena of `tasks` threads. Pieces of
// the etree weigh at most 1/(4 tasks) of the total, so that oneTBB can
// balance them; one task: one piece, the plain sequential sweep.
template <class PhaseDone>
void build_structure(SymbolicFactor& S, const CscMatrix& A, const Ordering& ordering, const SymbolicOptions& opt,
                     int tasks, const PhaseDone& phase_done) {
  const int32_t n = S.n;
  const int chunks = std::min(tasks, kMaxGraphChunks);
  const auto bound = [tasks](int64_t total) { return tasks <= 1 ? total : std::max<int64_t>(1, total / (4 * tasks)); };
  // (1) etree in the given order, then renumber by its postorder; the
  // pattern hash (sequential by nature) meanwhile.
  HalfGraph g;
  const auto etree_and_postorder = [&] {
    permuted_half_graph(A, ordering.iperm, Half::Below, chunks, g);
    HostVector<int32_t> parent0 = elimination_tree(n, g.ptr, g.idx);
    const HostVector<int32_t> post = tree_postorder(parent0);
    HostVector<int32_t> ipost(n);
    for (int32_t k = 0; k < n; ++k) ipost[post[k]] = k;
    S.perm.resize(n);
    S.iperm.resize(n);
    for (int32_t k = 0; k < n; ++k) {
      S.perm[k] = ordering.perm[post[k]];
      S.iperm[S.perm[k]] = k;
    }
    S.parent.resize(n);
    for (int32_t k = 0; k < n; ++k) {
      const int32_t p0 = parent0[post[k]];
      S.parent[k] = p0 < 0 ? -1 : ipost[p0];
    }
  };
  const auto hash = [&] { S.a_pattern_hash = pattern_hash(A); };
  if (tasks > 1) {
    tbb::parallel_invoke(hash, etree_and_postorder);
  } else {
    hash();
    etree_and_postorder();
  }
  phase_done();
  permuted_half_graph(A, S.iperm, Half::Above, chunks, g);
  phase_done();

  // (2) column counts over the subtrees of the (now postordered) etree.
  {
    HostVector<int64_t> w(n);
    for (int32_t k = 0; k < n; ++k) w[k] = 1 + g.ptr[k + 1] - g.ptr[k];
    const SubtreePartition part = subtree_partition(S.parent, std::move(w), bound(g.ptr[n] + n));
    S.col_count = column_counts_postordered(n, g.ptr, g.idx, S.parent, part);
  }
  S.nnz_exact = 0;
  for (int32_t c : S.col_count) S.nnz_exact += c;
  S.etree_height = tree_height(S.parent);
  phase_done();

  // (3) supernodes.
  S.super_first_col = relaxed_supernodes(S.parent, S.col_count, opt);
  const int32_t ns = S.ns = static_cast<int32_t>(S.super_first_col.size()) - 1;
  S.col_to_super.resize(n);
  for (int32_t s = 0; s < ns; ++s)
    for (int32_t j = S.super_first_col[s]; j < S.super_first_col[s + 1]; ++j) S.col_to_super[j] = s;
  S.super_parent.resize(ns);
  for (int32_t s = 0; s < ns; ++s) {
    const int32_t p = S.parent[S.super_first_col[s + 1] - 1];
    S.super_parent[s] = p < 0 ? -1 : S.col_to_super[p];
  }
  phase_done();

  // (4) row structures over the subtrees of the supernodal etree.
  {
    HostVector<int64_t> w(ns);
    int64_t total = 0;
    for (int32_t s = 0; s < ns; ++s) {
      const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
      w[s] = (l - f) + S.col_count[l - 1] + (g.ptr[l] - g.ptr[f]);
      total += w[s];
    }
    const SubtreePartition part = subtree_partition(S.super_parent, std::move(w), bound(total));
    supernode_rows(S, g.ptr, g.idx, part);
  }
  phase_done();
  // (5) the rest: assembly map, update lists, sizes.
  g = {};  // freed before the assembly map's buffers
  complete_symbolic_with(S, A, true, chunks);
}

}  // namespace

std::shared_ptr<const SymbolicFactor> analyze(const CscMatrix& A, const Ordering& ordering, const SymbolicOptions& opt,
                                              const RunContext& ctx) {
  ctx.check_cancel();
  check_lower(A);
  const int32_t n = A.ncols;
  if (static_cast<int32_t>(ordering.perm.size()) != n || static_cast<int32_t>(ordering.iperm.size()) != n)
    fail(ErrorCode::BadUsage, "ordering has " + std::to_string(ordering.perm.size()) + " entries for a matrix of " +
                                  std::to_string(n) + " columns");
  for (int32_t k = 0; k < n; ++k) {
    const int32_t i = ordering.perm[k];
    if (i < 0 || i >= n || ordering.iperm[i] != k) fail(ErrorCode::BadUsage, "ordering is not a permutation");
  }
  auto S = std::make_shared<SymbolicFactor>();
  S->n = n;
  S->a_nnz = A.nnz();
  // Progress by phase (each O(nnz(A)) or O(nnz(L))), ticked inside the long
  // loops too: a C host's chances to cancel come at least every ~20 ms.
  ProgressTicker ticker(ctx, "symbolic analysis", 6.0);
  const CancelScope scope(ticker);  // the loops below (this thread's) are cancel points
  const auto phase_done = [&] {
    ctx.check_cancel();
    ticker.add(1.0);
  };

  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  // Small matrices take ~1 ms: waking workers would cost more than they save.
  const int tasks = n < kParallelMinColumns ? 1 : std::max(1, threads);
  // One task: no oneTBB algorithm runs, so no arena is needed either (an
  // arena of another concurrency, entered from a oneTBB worker, would be a
  // fresh one per call: task_arenas.hpp).
  if (tasks == 1) build_structure(*S, A, ordering, opt, 1, phase_done);
  else run_with_threads(tasks, [&] { build_structure(*S, A, ordering, opt, tasks, phase_done); });
  ticker.add(1.0);
  return S;
}

RowStructure row_structure(const SymbolicFactor& S) {
  RowStructure R;
  R.row_ptr.assign(static_cast<size_t>(S.n) + 1, 0);
  for (int32_t s = 0; s < S.ns; ++s) {
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    for (int64_t p = S.super_row_ptr[s]; p < S.super_row_ptr[s + 1]; ++p) {
      const int32_t r = S.super_rows[p];
      R.row_ptr[r + 1] += std::min(r, l) - f;  // columns f..min(r,l)-1 of s lie left of row r
    }
  }
  for (int32_t i = 0; i < S.n; ++i) R.row_ptr[i + 1] += R.row_ptr[i];
  R.cols.resize(static_cast<size_t>(R.row_ptr[S.n]));
  HostVector<int64_t> next(R.row_ptr.begin(), R.row_ptr.end() - 1);
  for (int32_t s = 0; s < S.ns; ++s) {  // ascending s and c: each row's columns come out sorted
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    for (int64_t p = S.super_row_ptr[s]; p < S.super_row_ptr[s + 1]; ++p) {
      const int32_t r = S.super_rows[p];
      for (int32_t c = f; c < std::min(r, l); ++c) R.cols[next[r]++] = c;
    }
  }
  return R;
}

}  // namespace locus
