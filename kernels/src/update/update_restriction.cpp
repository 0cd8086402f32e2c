// Step (1) of the factor-once update (thesis §5.5): the structure of L
// restricted to I, the storage of the result and its symbolic factor; the
// passes themselves are in restricted_structure.cpp.
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <memory>

#include "factor_update_call.hpp"
#include "submatrix_extraction.hpp"

namespace locus {

using update_detail::complete_structure;
using update_detail::postorder_in_place;
using update_detail::restrict_structure;
using update_detail::seconds_since;
using update_detail::submatrix_from_map;

namespace {

// First touches of a fresh factor's pages, done by the second thread while the
// first one finishes the structure (the value offsets need the whole
// restricted structure; its size is known once the supernodes are restricted).
// Only for results of at least FactorUpdateOptions::prefault_min_bytes (32 MB):
// glibc serves smaller blocks again from the heap, already mapped, while
// larger ones are always a fresh mapping whose every page faults, and the
// faults of two threads overlap (costs: docs/factor_update.md). Every value is
// written again later (copied or recomputed), so what this writes never shows;
// it stops before anything else writes the values.
class Prefault {
 public:
  Prefault(double* data, int64_t count, bool active) : data_(data), count_(count) {
    if (active) tg_.run([this] { run(); });
  }
  ~Prefault() { stop(); }
  void stop() {
    stop_.store(true, std::memory_order_relaxed);
    tg_.wait();
  }

 private:
  void run() {
    constexpr int64_t kPage = 4096 / sizeof(double), kChunk = 64 * kPage;  // a stop check per 256 KB
    for (int64_t c0 = 0; c0 < count_ && !stop_.load(std::memory_order_relaxed); c0 += kChunk) {
      const int64_t c1 = std::min(count_, c0 + kChunk);
      for (int64_t i = c0; i < c1; i += kPage) data_[i] = 0.0;
    }
  }
  double* data_;
  int64_t count_;
  std::atomic<bool> stop_{false};
  tbb::task_group tg_;
};

}  // namespace

// (1) The restricted structure in L's order (then postordered if needed), the
// result's storage and its symbolic factor; the one-shot path also gathers
// A_II here (the prepared one extracts it beside the later steps).
void FactorUpdater::Call::restrict_to_set() {
  std::vector<int32_t>& col_new = u.col_new_;
  maps_filled = true;
  for (int32_t c = 0; c < m; ++c) {
    col_new[gcol[c]] = c;
    ++u.in_super_[S.col_to_super[gcol[c]]];
  }
  R = restrict_structure(S, col_new, gcol, two_threads);
  int64_t values_total = 0;
  for (int32_t s = 0; s < R.ns; ++s)
    values_total += (R.row_ptr[s + 1] - R.row_ptr[s]) * (R.first_col[s + 1] - R.first_col[s]);
  // The result's storage, sized once: the postorder below permutes the
  // supernodes but keeps their total. Not initialized (DefaultInitAllocator).
  // A borrowing update sizes its own blocks after marking instead.
  if (!borrow) out.factor.values.resize(static_cast<size_t>(values_total));
  Prefault prefault(out.factor.values.data(), values_total,
                    !borrow && two_threads &&
                        values_total * static_cast<int64_t>(sizeof(double)) >= opt.prefault_min_bytes);
  st.reordered = postorder_in_place(R, two_threads);
  if (st.reordered)
    for (int32_t c = 0; c < m; ++c) col_new[R.gcol[c]] = c;
  Sp = restricted_symbolic();
  if (prepared) {
    complete_structure(*Sp, two_threads);  // A_II and its assembly map come later, beside marking and copying
  } else {
    out.A_sub = submatrix_from_map(u.A_, out.vertices, u.local_);
    complete_symbolic(*Sp, out.A_sub);  // value offsets, assembly map, update lists, column etree
  }
  st.supernodes = Sp->ns;
  st.nnz_stored = Sp->nnz_L;
  st.values_stored = Sp->super_value_ptr[Sp->ns];
  st.structure_s = seconds_since(t0);
  ctx.check_cancel();
  prefault.stop();  // before anything else writes the values
}

// The symbolic factor of A_II from R: perm in local indices, supernodes, rows
// (moved out of R, which keeps row_ptr and rowpos for the copy).
std::shared_ptr<SymbolicFactor> FactorUpdater::Call::restricted_symbolic() {
  auto F = std::make_shared<SymbolicFactor>();
  F->n = m;
  F->perm.resize(m);
  F->iperm.resize(m);
  for (int32_t c = 0; c < m; ++c) {
    F->perm[c] = local_of(S.perm[R.gcol[c]]);
    F->iperm[F->perm[c]] = c;
  }
  F->ns = R.ns;
  F->super_first_col = R.first_col;
  F->col_to_super.resize(m);
  for (int32_t s = 0; s < R.ns; ++s)
    for (int32_t c = R.first_col[s]; c < R.first_col[s + 1]; ++c) F->col_to_super[c] = s;
  F->super_parent = R.parent;
  F->super_row_ptr = R.row_ptr;
  F->super_rows = std::move(R.rows);
  return F;
}

}  // namespace locus
