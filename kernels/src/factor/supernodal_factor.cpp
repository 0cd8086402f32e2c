// Left-looking supernodal Cholesky with subtree parallelism (kernels/include/locus/kernels/factor/supernodal_factor.hpp).
//
// Supernode s is computed from its assembled block of A minus the updates of
// every descendant d in its update list (ascending, so the sum order is fixed):
// C = L_d[p1:, :] * L_d[p1:p2, :]^T with dsyrk/dgemm, scattered into s through a
// row map; then dpotrf on the diagonal block and dtrsm below it.
//
// Parallelism: the supernodal etree is cut into subtrees of at most 1/(16 p) of
// the total work, each factored sequentially in postorder by one task; above
// the cut, the children of a branching node run as parallel tasks before it.
// A supernode only reads finished descendants and writes its own block, so no
// locks are needed and the result does not depend on the schedule.
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/core/host_allocator.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "locus/kernels/factor/blas.hpp"
#include "locus/kernels/factor/dense_small.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

// Neither buffer needs zeros: rowmap is written for a supernode's rows before
// they are read, and C is overwritten by each update (no zero-fill of sizes
// that can reach megabytes per thread and per call).
struct Workspace {
  std::vector<int32_t, DefaultInitAllocator<int32_t>> rowmap;  // global row -> local row in the current supernode
  std::vector<double, DefaultInitAllocator<double>> update;    // dense update block C
  std::vector<int32_t, DefaultInitAllocator<int32_t>> rel;     // target row (in s) of each row of C
};

class Factorizer {
 public:
  Factorizer(NumericFactor& f, const CscMatrix* A, const RunContext& ctx, const uint8_t* only = nullptr,
             const SupernodeAssembler* assemble = nullptr)
      : F_(f), S_(*f.symbolic), A_(A), ctx_(ctx), only_(only), assemble_(assemble),
        ws_([this] {
          Workspace w;
          w.rowmap.resize(S_.n);
          w.rel.resize(static_cast<size_t>(std::max<int32_t>(1, S_.max_super_rows)));
          w.update.resize(static_cast<size_t>(std::max<int64_t>(1, S_.max_update_entries)));
          return w;
        }) {}

  void run() {
    const int32_t ns = S_.ns;
    if (ns == 0) return;
    // Work per subtree (flops) and first descendant of each supernode.
    work_.assign(ns, 0.0);
    first_desc_.resize(ns);
    for (int32_t s = 0; s < ns; ++s) first_desc_[s] = s;
    for (int32_t s = 0; s < ns; ++s) {
      if (!only_ || only_[s]) work_[s] += own_work(s);
      const int32_t p = S_.super_parent[s];
      if (p >= 0) {
        work_[p] += work_[s];
        first_desc_[p] = std::min(first_desc_[p], first_desc_[s]);
      }
    }
    child_ptr_.assign(static_cast<size_t>(ns) + 1, 0);
    children_.resize(ns);
    for (int32_t s = 0; s < ns; ++s)
      if (S_.super_parent[s] >= 0) ++child_ptr_[S_.super_parent[s] + 1];
    for (int32_t s = 0; s < ns; ++s) child_ptr_[s + 1] += child_ptr_[s];
    {
      HostVector<int32_t> next(child_ptr_.begin(), child_ptr_.end() - 1);
      for (int32_t s = 0; s < ns; ++s)
        if (S_.super_parent[s] >= 0) children_[next[S_.super_parent[s]]++] = s;
    }
    double total = 0;
    HostVector<int32_t> roots;
    for (int32_t s = 0; s < ns; ++s)
      if (S_.super_parent[s] < 0) { roots.push_back(s); total += work_[s]; }
    total_work_ = total;
    if (ctx_.progress) ctx_.report(0.0, kPhase);

    blas::SingleThreaded single;
    const int threads = ctx_.threads > 0 ? ctx_.threads : tbb::this_task_arena::max_concurrency();
    // Always with the requested concurrency: the large-supernode path uses
    // nested parallel loops, which must not spill onto other cores.
    // Below ~1 ms of work, waking workers costs more than they save: their
    // spin-waiting burned >90% of the CPU time of 1000 50-vertex factorizations.
    constexpr double kParallelMinWork = 2e6;
    if (threads <= 1 || total < kParallelMinWork) {
      run_with_threads(1, [&] {
        for (int32_t s = 0; s < ns; ++s) factor_one(s);
      });
    } else {
      threshold_ = total / (16.0 * threads);
      run_with_threads(threads, [&] {
        tbb::task_group tg;
        for (int32_t r : roots) tg.run([this, r] { process(r); });
        tg.wait();
      });
    }
    if (ctx_.progress) ctx_.report(1.0, kPhase);
  }

 private:
  static constexpr const char* kPhase = "numeric factorization";

  // Flops of supernode s alone (~ its potrf/trsm and the updates it receives): the progress and scheduling weight.
  double own_work(int32_t s) const {
    const double m = S_.nrows(s), k = S_.ncols(s);
    return k * m * m - k * k * m + k * k * k / 3.0 + m;
  }

  // Progress by work done: at most one report per ~20 ms,
  // from whichever thread finishes work then. A C host cancels by returning
  // nonzero from its progress callback, so these reports are also its chances
  // to stop a factorization (check_cancel runs before every supernode and
  // every column block of a large one).
  void progress_done(double work) {
    if (!ctx_.progress) return;
    const double done = done_work_.fetch_add(work, std::memory_order_relaxed) + work;
    const int64_t now = std::chrono::duration_cast<std::chrono::microseconds>(
                            std::chrono::steady_clock::now().time_since_epoch()).count();
    int64_t last = last_report_us_.load(std::memory_order_relaxed);
    if (now - last < kReportEveryUs) return;
    if (!last_report_us_.compare_exchange_strong(last, now)) return;  // another thread reports this tick
    ctx_.report(total_work_ > 0 ? std::min(1.0, done / total_work_) : 1.0, kPhase);
  }
  static constexpr int64_t kReportEveryUs = 20000;

  // Factors the subtree of s: children first (in parallel when large), then the chain above.
  void process(int32_t s) {
    HostVector<int32_t> chain{s};
    while (work_[chain.back()] > threshold_ && child_ptr_[chain.back() + 1] - child_ptr_[chain.back()] == 1)
      chain.push_back(children_[child_ptr_[chain.back()]]);
    const int32_t bottom = chain.back();
    if (work_[bottom] <= threshold_) {
      chain.pop_back();
      for (int32_t q = first_desc_[bottom]; q <= bottom; ++q) factor_one(q);
    } else {
      tbb::task_group tg;
      for (int32_t c = child_ptr_[bottom]; c < child_ptr_[bottom + 1]; ++c) {
        const int32_t child = children_[c];
        tg.run([this, child] { process(child); });
      }
      tg.wait();
    }
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) factor_one(*it);
  }

  void factor_one(int32_t s) {
    if (only_ && !only_[s]) return;
    ctx_.check_cancel();
    if (is_large(s)) {
      factor_large(s);
      return;
    }
    Workspace& w = ws_.local();
    const int32_t f = S_.super_first_col[s];
    const int32_t k = S_.ncols(s), m = S_.nrows(s);
    const int32_t* rows = S_.super_rows.data() + S_.super_row_ptr[s];
    double* Ls = F_.block(s);  // an own block: only own blocks are (re)computed
    std::memset(Ls, 0, sizeof(double) * static_cast<size_t>(m) * k);
    for (int32_t t = 0; t < m; ++t) w.rowmap[rows[t]] = t;
    if (assemble_) {
      (*assemble_)(s, 0, k, Ls, w.rowmap.data());
    } else {
      for (int64_t q = S_.a_super_ptr[s]; q < S_.a_super_ptr[s + 1]; ++q)
        Ls[S_.a_dst[q] - S_.super_value_ptr[s]] = A_->values[S_.a_src[q]];
    }

    for (int64_t u = S_.update_ptr[s]; u < S_.update_ptr[s + 1]; ++u) apply_update(S_.update_from[u], f, k, m, Ls, w);

    const char lo = 'L';
    int info = 0;
    if (k <= kSmallPanelCols) {
      info = dense::panel_cholesky(m, k, Ls);  // potrf and trsm in one pass
    } else {
      dpotrf_(&lo, &k, Ls, &m, &info);
    }
    if (info != 0) {
      const int32_t col = f + info - 1;
      fail(ErrorCode::Numerical,
           "matrix is not positive definite at vertex " + std::to_string(S_.perm[col]) + " (factor column " +
               std::to_string(col) + ")",
           ErrorLocation{S_.perm[col], col});
    }
    if (m > k && k > kSmallPanelCols) {
      const int mk = m - k;
      const double one = 1.0;
      const char r = 'R', t = 'T', nu = 'N';
      dtrsm_(&r, &lo, &t, &nu, &mk, &k, &one, Ls, &m, Ls + k, &m);
    }
    progress_done(own_work(s));
  }

  // Supernodes near the root are few and wide: they are factored with
  // parallelism inside (column blocks of the update gathering, then a blocked
  // right-looking panel Cholesky). The choice depends only on the supernode's
  // size, never on the thread count, so the arithmetic is the same for any
  // number of threads.
  static constexpr int kBlock = 96;
  // Below these sizes the blocks go to kernels/include/locus/kernels/factor/dense_small.hpp instead of
  // OpenBLAS, whose per-call buffer lock serializes threads on small calls.
  static constexpr int kSmallPanelCols = 16;
  static constexpr int64_t kSmallUpdateFlops = 131072;
  // From a bit over one block: the gather then splits into two column-block
  // tasks. On the recomputed top of a factor-once update (chains of medium
  // supernodes) that cut the factor phase by 5-9% at two threads (104k
  // vertices); the whole factorization's time did not change.
  bool is_large(int32_t s) const {
    const double k = S_.ncols(s), m = S_.nrows(s);
    return k >= kBlock + 16 && k * k * m >= 2.0e6;
  }

  void factor_large(int32_t s) {
    const int32_t f = S_.super_first_col[s];
    const int32_t k = S_.ncols(s), m = S_.nrows(s);
    const int32_t* rows = S_.super_rows.data() + S_.super_row_ptr[s];
    double* Ls = F_.block(s);  // an own block: only own blocks are (re)computed
    const int nblocks = (k + kBlock - 1) / kBlock;
    // Assembly and descendant updates, one task per block of kBlock columns of s.
    tbb::parallel_for(0, nblocks, [&](int b) {
      Workspace& w = ws_.local();
      const int32_t c0 = b * kBlock, c1 = std::min(k, c0 + kBlock);
      std::memset(Ls + static_cast<int64_t>(c0) * m, 0, sizeof(double) * static_cast<size_t>(m) * (c1 - c0));
      for (int32_t t = 0; t < m; ++t) w.rowmap[rows[t]] = t;
      if (assemble_) {
        (*assemble_)(s, c0, c1, Ls, w.rowmap.data());
      } else {
        for (int64_t q = S_.a_super_ptr[s]; q < S_.a_super_ptr[s + 1]; ++q) {
          const int64_t off = S_.a_dst[q] - S_.super_value_ptr[s];
          if (off >= static_cast<int64_t>(c0) * m && off < static_cast<int64_t>(c1) * m) Ls[off] = A_->values[S_.a_src[q]];
        }
      }
      for (int64_t u = S_.update_ptr[s]; u < S_.update_ptr[s + 1]; ++u) {
        ctx_.check_cancel();  // a root supernode alone can take seconds: stay within ~100 ms of a cancel
        progress_done(0.0);   // and give a C host's progress callback its chance to ask for it
        apply_update(S_.update_from[u], f + c0, c1 - c0, m, Ls + static_cast<int64_t>(c0) * m, w, f);
      }
    });
    // Blocked right-looking Cholesky of the m x k panel.
    const char lo = 'L', nt = 'N', tr = 'T', right = 'R', nu = 'N';
    const double one = 1.0, mone = -1.0;
    for (int32_t j0 = 0; j0 < k; j0 += kBlock) {
      ctx_.check_cancel();
      const int jb = std::min<int32_t>(kBlock, k - j0);
      progress_done(own_work(s) * jb / k);  // the panel's share (reported as it starts: a chance to cancel)
      double* Djj = Ls + static_cast<int64_t>(j0) * m + j0;
      int info = 0;
      dpotrf_(&lo, &jb, Djj, &m, &info);
      if (info != 0) {
        const int32_t col = f + j0 + info - 1;
        fail(ErrorCode::Numerical,
             "matrix is not positive definite at vertex " + std::to_string(S_.perm[col]) + " (factor column " +
                 std::to_string(col) + ")",
             ErrorLocation{S_.perm[col], col});
      }
      const int32_t r0 = j0 + jb;
      if (r0 >= m) break;
      const int nrb = (m - r0 + 2 * kBlock - 1) / (2 * kBlock);
      tbb::parallel_for(0, nrb, [&](int b) {
        if (ctx_.cancelled()) return;  // the panel is abandoned: the check below throws
        const int32_t a0 = r0 + b * 2 * kBlock;
        const int rows_b = std::min<int32_t>(2 * kBlock, m - a0);
        dtrsm_(&right, &lo, &tr, &nu, &rows_b, &jb, &one, Djj, &m, Ls + static_cast<int64_t>(j0) * m + a0, &m);
      });
      if (r0 >= k) continue;
      // Trailing columns r0..k-1 of the panel (all rows below their diagonal).
      const int ntb = (k - r0 + kBlock - 1) / kBlock;
      // One panel's trailing update takes ~0.3 s on a 416k-vertex root supernode:
      // each column block is a chance to cancel (reported, and checked).
      tbb::parallel_for(0, ntb, [&](int b) {
        if (ctx_.cancelled()) return;
        progress_done(0.0);
        const int32_t c0 = r0 + b * kBlock;
        const int cw = std::min<int32_t>(kBlock, k - c0);
        const double* Lc = Ls + static_cast<int64_t>(j0) * m + c0;  // rows c0.. of the current block column
        double* T = Ls + static_cast<int64_t>(c0) * m + c0;
        dsyrk_(&lo, &nt, &cw, &jb, &mone, Lc, &m, &one, T, &m);
        const int below = m - c0 - cw;
        if (below > 0) dgemm_(&nt, &tr, &below, &cw, &jb, &mone, Lc + cw, &m, Lc, &m, &one, T + cw, &m);
      });
    }
    ctx_.check_cancel();  // a cancel during the last panel's blocks: the supernode is incomplete
  }

  void apply_update(int32_t d, int32_t f, int32_t k, int32_t m, double* Ls, Workspace& w) {
    apply_update(d, f, k, m, Ls, w, f);
  }

  // Update of columns [f, f + k) of the supernode whose first column is sf and
  // whose block starts at Ls - (f - sf) * m: C = Ld[p1:, :] * Ld[p1:p2, :]^T.
  void apply_update(int32_t d, int32_t f, int32_t k, int32_t m, double* Ls, Workspace& w, int32_t sf) {
    const int32_t md = S_.nrows(d), kd = S_.ncols(d);
    const int32_t* rd = S_.super_rows.data() + S_.super_row_ptr[d];
    const double* Ld = std::as_const(F_).block(d);  // own or borrowed
    const int32_t p1 = static_cast<int32_t>(std::lower_bound(rd + kd, rd + md, f) - rd);
    const int32_t p2 = static_cast<int32_t>(std::lower_bound(rd + p1, rd + md, f + k) - rd);
    const int mm = md - p1, kk = p2 - p1;
    if (kk == 0) return;  // d has no row in this column range
    double* C = w.update.data();
    // C(mm x kk) = Ld[p1:md, :] * Ld[p1:p2, :]^T: lower triangle of the top square by dsyrk, the rest by dgemm.
    if (static_cast<int64_t>(mm) * kk * kd <= kSmallUpdateFlops) {
      dense::syrk_gemm_lower(mm, kk, kd, Ld + p1, md, C);
    } else {
      const double one = 1.0, zero = 0.0;
      const char lo = 'L', nt = 'N', tr = 'T';
      dsyrk_(&lo, &nt, &kk, &kd, &one, Ld + p1, &md, &zero, C, &mm);
      if (mm > kk) {
        const int rest = mm - kk;
        dgemm_(&nt, &tr, &rest, &kk, &kd, &one, Ld + p2, &md, Ld + p1, &md, &zero, C + kk, &mm);
      }
    }
    // Scatter-subtract into s. When d's rows p1.. map to consecutive rows of s the
    // target columns are contiguous runs; the general path uses the row map.
    const int32_t* rmap = w.rowmap.data();
    double* base = Ls - static_cast<int64_t>(f - sf) * m;  // column sf of the supernode
    const int32_t r0 = rmap[rd[p1]];
    if (rmap[rd[md - 1]] - r0 == mm - 1) {  // d's rows are consecutive rows of s: same subtractions, vectorizable
      for (int jj = 0; jj < kk; ++jj) {
        double* dst = base + static_cast<int64_t>(rd[p1 + jj] - sf) * m + r0;
        const double* src = C + static_cast<int64_t>(jj) * mm;
        for (int ii = jj; ii < mm; ++ii) dst[ii] -= src[ii];
      }
      return;
    }
    // Target rows of d's rows p1.. looked up once, not once per column: the
    // scatter then does one indirection per entry instead of two.
    int32_t* rel = w.rel.data();
    for (int ii = 0; ii < mm; ++ii) rel[ii] = rmap[rd[p1 + ii]];
    for (int jj = 0; jj < kk; ++jj) {
      double* dst = base + static_cast<int64_t>(rd[p1 + jj] - sf) * m;
      const double* src = C + static_cast<int64_t>(jj) * mm;
      for (int ii = jj; ii < mm; ++ii) dst[rel[ii]] -= src[ii];
    }
  }

  NumericFactor& F_;
  const SymbolicFactor& S_;
  const CscMatrix* A_;  // assembled through the symbolic factor's map unless assemble_ is set
  const RunContext& ctx_;
  const uint8_t* only_;  // if set, factor only supernodes with only_[s] != 0
  const SupernodeAssembler* assemble_;
  tbb::enumerable_thread_specific<Workspace> ws_;
  HostVector<double> work_;
  HostVector<int32_t> first_desc_, child_ptr_, children_;
  double threshold_ = 0;
  double total_work_ = 0;
  std::atomic<double> done_work_{0.0};
  std::atomic<int64_t> last_report_us_{0};
};

// factorize_supernodes: the storage matches the symbolic factor and no block
// to recompute is borrowed.
void check_recomputable(const NumericFactor& f, std::span<const uint8_t> refactor) {
  if (!storage_matches_symbolic(f))
    fail(ErrorCode::BadUsage, "factorize_supernodes: factor values are not sized to its symbolic factor");
  if (!f.borrows()) return;
  for (int32_t s = 0; s < f.symbolic->ns; ++s)
    if (f.borrowed[s] && refactor[s])
      fail(ErrorCode::BadUsage, "factorize_supernodes: supernode " + std::to_string(s) +
                                    " is borrowed from another factor and cannot be recomputed in place");
}

void check_pattern(const SymbolicFactor& S, const CscMatrix& A) {
  if (A.ncols != S.n || A.nrows != S.n || A.nnz() != S.a_nnz ||
      static_cast<int64_t>(A.values.size()) != A.nnz() || pattern_hash(A) != S.a_pattern_hash)
    fail(ErrorCode::BadUsage, "matrix does not have the sparsity pattern the symbolic factor was built for");
  if (static_cast<int64_t>(S.a_src.size()) != S.a_nnz || static_cast<int64_t>(S.a_super_ptr.size()) != S.ns + 1)
    fail(ErrorCode::BadUsage, "the symbolic factor's assembly map was released (a factor-once operator)");
  // A NaN or infinite entry would pass dpotrf silently and poison every solve.
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p)
      if (!std::isfinite(A.values[p]))
        fail(ErrorCode::Numerical, "matrix entry (" + std::to_string(A.rowind[p]) + ", " + std::to_string(j) +
                                       ") is not finite (vertex " + std::to_string(j) + ")");
}

}  // namespace

bool storage_matches_symbolic(const NumericFactor& f) {
  if (!f.symbolic) return false;
  const SymbolicFactor& S = *f.symbolic;
  if (!f.borrows()) return static_cast<int64_t>(f.values.size()) == S.super_value_ptr[S.ns];
  if (static_cast<int32_t>(f.borrowed.size()) != S.ns || static_cast<int32_t>(f.own_offset.size()) != S.ns) return false;
  for (int32_t s = 0; s < S.ns; ++s) {
    if (f.borrowed[s]) continue;
    const int64_t size = S.super_value_ptr[s + 1] - S.super_value_ptr[s];
    if (f.own_offset[s] < 0 || f.own_offset[s] + size > static_cast<int64_t>(f.values.size())) return false;
  }
  return true;
}

NumericFactor factorize(std::shared_ptr<const SymbolicFactor> symbolic, const CscMatrix& A, const RunContext& ctx) {
  if (!symbolic) fail(ErrorCode::BadUsage, "factorize: no symbolic factor");
  check_pattern(*symbolic, A);
  check_factor_memory(*symbolic, ctx);  // refuse up front rather than be killed by the OS
  NumericFactor f;
  f.symbolic = std::move(symbolic);
  f.values.resize(static_cast<size_t>(f.symbolic->super_value_ptr[f.symbolic->ns]));
  Factorizer(f, &A, ctx).run();
  return f;
}

void refactorize(NumericFactor& f, const CscMatrix& A, const RunContext& ctx) {
  if (!f.symbolic) fail(ErrorCode::BadUsage, "refactorize: factor has no symbolic part");
  check_pattern(*f.symbolic, A);
  // Every block is recomputed, so a factor that borrowed blocks owns them all again.
  f.borrowed.clear();
  f.own_offset.clear();
  f.lender.reset();
  f.values.resize(static_cast<size_t>(f.symbolic->super_value_ptr[f.symbolic->ns]));
  Factorizer(f, &A, ctx).run();
}

void factorize_supernodes(NumericFactor& f, const CscMatrix& A, std::span<const uint8_t> refactor, const RunContext& ctx) {
  if (!f.symbolic) fail(ErrorCode::BadUsage, "factorize_supernodes: factor has no symbolic part");
  check_pattern(*f.symbolic, A);
  if (static_cast<int64_t>(refactor.size()) != f.symbolic->ns)
    fail(ErrorCode::BadUsage, "factorize_supernodes: mask has " + std::to_string(refactor.size()) + " entries for " +
                                  std::to_string(f.symbolic->ns) + " supernodes");
  check_recomputable(f, refactor);
  Factorizer(f, &A, ctx, refactor.data()).run();
}

void factorize_supernodes_assembled(NumericFactor& f, std::span<const uint8_t> refactor,
                                    const SupernodeAssembler& assemble, const RunContext& ctx) {
  if (!f.symbolic) fail(ErrorCode::BadUsage, "factorize_supernodes: factor has no symbolic part");
  if (static_cast<int64_t>(refactor.size()) != f.symbolic->ns)
    fail(ErrorCode::BadUsage, "factorize_supernodes: mask has " + std::to_string(refactor.size()) + " entries for " +
                                  std::to_string(f.symbolic->ns) + " supernodes");
  check_recomputable(f, refactor);
  Factorizer(f, nullptr, ctx, refactor.data(), &assemble).run();
}

}  // namespace locus
