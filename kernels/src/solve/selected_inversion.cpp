// Supernodal selected inversion (kernels/include/locus/kernels/solve/selected_inversion.hpp).
//
// Supernodes are visited from the root down. For supernode s, the rows below
// its columns are grouped by the ancestor supernode g that owns them (as in
// the left-looking factorization's update lists, read backwards); each group
// contributes two GEMMs with the block G = Z(rows of s from g on, columns of
// g that are rows of s), gathered from g's Z block. Independent subtrees are
// processed as parallel oneTBB tasks once their common ancestor is done; the
// arithmetic of each supernode does not depend on the schedule.
#include "locus/kernels/solve/selected_inversion.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <string>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

struct Work {
  std::vector<double> U, ZRJ, G;
};

class Inverter {
 public:
  Inverter(const NumericFactor& F, SelectedInverse& Z) : F_(F), S_(*F.symbolic), Z_(Z) {}

  void one(int32_t s, Work& w) {
    const int32_t f = S_.super_first_col[s], k = S_.ncols(s), m = S_.nrows(s), below = m - k;
    const int32_t* rows = S_.super_rows.data() + S_.super_row_ptr[s];
    const double* L = F_.block(s);
    double* Zs = Z_.values.data() + S_.super_value_ptr[s];
    const char lo = 'L', nu = 'N', nt = 'N', tr = 'T', right = 'R';
    const double one = 1.0, zero = 0.0, mone = -1.0;
    int info = 0;
    // Top square: W = L11^{-1}, then W^T W = (L11 L11^T)^{-1}.
    for (int j = 0; j < k; ++j)
      for (int i = j; i < k; ++i) Zs[static_cast<int64_t>(j) * m + i] = L[static_cast<int64_t>(j) * m + i];
    dtrtri_(&lo, &nu, &k, Zs, &m, &info);
    if (info != 0) fail(ErrorCode::Numerical, "selected inversion: singular diagonal block at factor column " + std::to_string(f + info - 1));
    dlauum_(&lo, &k, Zs, &m, &info);
    // The strict upper triangle of the square is not part of Z's storage; it held
    // whatever the allocation held (DefaultInitAllocator) and the GEMM below
    // would carry that on. Zeroed, so every byte of Z is a function of the input
    // alone (bit-identical for any thread count and heap state).
    for (int j = 1; j < k; ++j) std::fill(Zs + static_cast<int64_t>(j) * m, Zs + static_cast<int64_t>(j) * m + j, 0.0);
    if (below == 0) return;
    // U = L21 L11^{-1} (below x k).
    w.U.resize(static_cast<size_t>(below) * k);
    for (int j = 0; j < k; ++j)
      std::copy(L + static_cast<int64_t>(j) * m + k, L + static_cast<int64_t>(j) * m + m, w.U.begin() + static_cast<int64_t>(j) * below);
    dtrsm_(&right, &lo, &nt, &nu, &below, &k, &one, L, &m, w.U.data(), &below);
    // Z_RJ = -Z_RR U, accumulated group by group.
    w.ZRJ.assign(static_cast<size_t>(below) * k, 0.0);
    int32_t t = k;
    while (t < m) {
      const int32_t g = S_.col_to_super[rows[t]];
      const int32_t gf = S_.super_first_col[g], gl = S_.super_first_col[g + 1], gm = S_.nrows(g);
      int32_t t2 = t;
      while (t2 < m && rows[t2] < gl) ++t2;
      const int ng = t2 - t;         // rows of s that are columns of g
      const int nr = m - t;          // rows of s from g on (all are rows of g)
      const int32_t* grows = S_.super_rows.data() + S_.super_row_ptr[g];
      const double* Zg = Z_.values.data() + S_.super_value_ptr[g];
      // Gather G (nr x ng): G(a, b) = Z(rows[t+a], rows[t+b]), lower part from g's block,
      // the upper triangle of the square part by symmetry.
      w.G.resize(static_cast<size_t>(nr) * ng);
      int32_t q = 0;  // position in g's rows (merge walk: rows of s from t on are rows of g)
      for (int a = 0; a < nr; ++a) {
        const int32_t r = rows[t + a];
        while (grows[q] < r) ++q;
        for (int b = 0; b < ng; ++b) {
          const int32_t c = rows[t + b] - gf;  // column of g
          if (a >= b) w.G[static_cast<int64_t>(b) * nr + a] = Zg[static_cast<int64_t>(c) * gm + q];
        }
      }
      for (int b = 0; b < ng; ++b)
        for (int a = 0; a < b; ++a) w.G[static_cast<int64_t>(b) * nr + a] = w.G[static_cast<int64_t>(a) * nr + b];
      const int off = t - k;  // row offset of this group inside ZRJ / U
      // ZRJ[off:, :] -= G * U[off:off+ng, :]
      dgemm_(&nt, &nt, &nr, &k, &ng, &mone, w.G.data(), &nr, w.U.data() + off, &below, &one, w.ZRJ.data() + off, &below);
      // ZRJ[off:off+ng, :] -= G[ng:, :]^T * U[off+ng:, :]
      const int rest = nr - ng;
      if (rest > 0)
        dgemm_(&tr, &nt, &ng, &k, &rest, &mone, w.G.data() + ng, &nr, w.U.data() + off + ng, &below, &one,
               w.ZRJ.data() + off, &below);
      t = t2;
    }
    // Z_JJ -= U^T Z_RJ (lower triangle used; the upper is cleared again after); store Z_RJ below.
    dgemm_(&tr, &nt, &k, &k, &below, &mone, w.U.data(), &below, w.ZRJ.data(), &below, &one, Zs, &m);
    for (int j = 1; j < k; ++j) std::fill(Zs + static_cast<int64_t>(j) * m, Zs + static_cast<int64_t>(j) * m + j, 0.0);
    for (int j = 0; j < k; ++j)
      std::copy(w.ZRJ.begin() + static_cast<int64_t>(j) * below, w.ZRJ.begin() + static_cast<int64_t>(j + 1) * below,
                Zs + static_cast<int64_t>(j) * m + k);
    (void)zero;
  }

  const NumericFactor& F_;
  const SymbolicFactor& S_;
  SelectedInverse& Z_;
};

}  // namespace

SelectedInverse selected_inversion(const NumericFactor& F, const RunContext& ctx) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "selected_inversion: empty factor");
  const SymbolicFactor& S = *F.symbolic;
  SelectedInverse Z;
  Z.symbolic = F.symbolic;
  Z.values.resize(static_cast<size_t>(S.super_value_ptr[S.ns]));  // (F's own values may be fewer: borrowed blocks)
  Inverter inv(F, Z);
  blas::SingleThreaded single;
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  if (threads <= 1) {
    Work w;
    for (int32_t s = S.ns - 1; s >= 0; --s) {
      ctx.check_cancel();
      inv.one(s, w);
    }
    return Z;
  }
  // Top-down: a supernode's children start once it is done.
  std::vector<int32_t> child_ptr(static_cast<size_t>(S.ns) + 1, 0), children(S.ns);
  for (int32_t s = 0; s < S.ns; ++s)
    if (S.super_parent[s] >= 0) ++child_ptr[S.super_parent[s] + 1];
  for (int32_t s = 0; s < S.ns; ++s) child_ptr[s + 1] += child_ptr[s];
  {
    std::vector<int32_t> next(child_ptr.begin(), child_ptr.end() - 1);
    for (int32_t s = 0; s < S.ns; ++s)
      if (S.super_parent[s] >= 0) children[next[S.super_parent[s]]++] = s;
  }
  // Subtree sizes decide whether a subtree is worth a task of its own.
  std::vector<int64_t> size(S.ns, 0);
  for (int32_t s = 0; s < S.ns; ++s) {
    size[s] += static_cast<int64_t>(S.nrows(s)) * S.ncols(s);
    if (S.super_parent[s] >= 0) size[S.super_parent[s]] += size[s];
  }
  const int64_t grain = std::max<int64_t>(1, static_cast<int64_t>(S.super_value_ptr[S.ns] / (16 * threads)));
  tbb::enumerable_thread_specific<Work> works;
  std::function<void(int32_t)> down = [&](int32_t s) {
    ctx.check_cancel();
    Work& w = works.local();
    inv.one(s, w);
    if (size[s] <= grain) {  // small subtree: sequential, parents before children (descending order)
      std::vector<int32_t> stack(children.begin() + child_ptr[s], children.begin() + child_ptr[s + 1]);
      while (!stack.empty()) {
        const int32_t c = stack.back();
        stack.pop_back();
        inv.one(c, w);
        stack.insert(stack.end(), children.begin() + child_ptr[c], children.begin() + child_ptr[c + 1]);
      }
      return;
    }
    tbb::task_group tg;
    for (int32_t q = child_ptr[s]; q < child_ptr[s + 1]; ++q) {
      const int32_t c = children[q];
      tg.run([&down, c] { down(c); });
    }
    tg.wait();
  };
  run_with_threads(threads, [&] {
    tbb::task_group tg;
    for (int32_t s = 0; s < S.ns; ++s)
      if (S.super_parent[s] < 0) tg.run([&down, s] { down(s); });
    tg.wait();
  });
  return Z;
}

std::vector<double> inverse_diagonal(const SelectedInverse& Z) {
  const SymbolicFactor& S = *Z.symbolic;
  std::vector<double> d(S.n);
  for (int32_t s = 0; s < S.ns; ++s) {
    const double* Zs = Z.values.data() + S.super_value_ptr[s];
    const int32_t m = S.nrows(s);
    for (int32_t j = 0; j < S.ncols(s); ++j) d[S.perm[S.super_first_col[s] + j]] = Zs[static_cast<int64_t>(j) * m + j];
  }
  return d;
}

double inverse_entry(const SelectedInverse& Z, int32_t i, int32_t j) {
  const SymbolicFactor& S = *Z.symbolic;
  if (i < 0 || j < 0 || i >= S.n || j >= S.n) fail(ErrorCode::BadUsage, "inverse_entry: vertex out of range");
  int32_t r = S.iperm[i], c = S.iperm[j];
  if (r < c) std::swap(r, c);
  const int32_t s = S.col_to_super[c];
  const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
  const int32_t* hit = std::lower_bound(rows, rows + S.nrows(s), r);
  if (hit == rows + S.nrows(s) || *hit != r)
    fail(ErrorCode::BadUsage, "inverse_entry: (" + std::to_string(i) + ", " + std::to_string(j) + ") is not on the pattern of L");
  return Z.values[S.super_value_ptr[s] + static_cast<int64_t>(c - S.super_first_col[s]) * S.nrows(s) + (hit - rows)];
}

}  // namespace locus
