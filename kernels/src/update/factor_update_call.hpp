// The state of one call of FactorUpdater::update (thesis §5.5) shared by the
// files of its steps: factor_update.cpp (the updater, the plan and the order of
// the steps), update_restriction.cpp (1, the restricted structure),
// update_marking.cpp (2, marking), update_copy.cpp (3, copying or borrowing the
// unmarked supernodes) and partial_refactorization.cpp (4, recomputing the
// marked ones; or the fresh factorization of a scattered set). Internal to
// kernels/src/update.
#pragma once
#include <tbb/task_arena.h>

#include <bit>
#include <chrono>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/kernels/update/factor_update.hpp"
#include "restricted_structure.hpp"

namespace locus {
namespace update_detail {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs f inside an arena of the context's thread budget (TBB owns the threads).
template <class F>
void in_arena(const RunContext& ctx, F&& f) {
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  if (threads <= 1) {
    f(1);
    return;
  }
  run_with_threads(threads, [&] { f(threads); });
}

}  // namespace update_detail

// One call of update(I). The steps hand each other the result being built, I's
// factor columns, the restricted structure and the marks; they run in the order
// update_impl lists. The destructor leaves the updater's maps all -1 / 0 again
// however the call ends (a refused set, a failed pivot, a cancellation).
struct FactorUpdater::Call {
  using clock = std::chrono::steady_clock;

  Call(FactorUpdater& updater, std::span<const int32_t> set, const RunContext& context, bool two)
      : u(updater), L(updater.L_), S(*updater.L_.symbolic), opt(updater.opt_), I(set), ctx(context),
        two_threads(two), prepared(!updater.ap_ptr_.empty()), borrow(updater.lender_ != nullptr) {}
  Call(const Call&) = delete;
  Call& operator=(const Call&) = delete;
  ~Call();

  // factor_update.cpp: the plan, the whole copy, the order of the steps.
  void plan();
  void copy_whole();
  void list_factor_columns();
  void finish_prepared();
  void finish_one_shot();
  void mark_and_copy();
  void extract_submatrix();
  // update_restriction.cpp: (1) the restricted structure and the result's storage.
  void restrict_to_set();
  std::shared_ptr<SymbolicFactor> restricted_symbolic();
  // update_marking.cpp: (2) the changed columns.
  void mark_changed();
  void walk(int32_t c);
  void count_marked();
  // update_copy.cpp: (3) the unmarked supernodes, copied or borrowed.
  void lay_out_borrowed();
  void copy_unmarked();
  void copy_supernodes(int32_t s0, int32_t s1);
  // partial_refactorization.cpp: (4) the marked supernodes; a scattered set from scratch.
  void refactor_fresh();
  void assemble_direct(int32_t s, int32_t c0, int32_t c1, double* block, const int32_t* rowmap) const;
  void refactor_marked(const SupernodeAssembler* direct);
  template <class Factorize>
  void factor_naming_vertices(const SymbolicFactor& Sf, Factorize&& run);
  // Local index of a vertex of I = its rank in the bit set: a popcount over a
  // prefix table of n/64 entries, which stays in cache where the n-sized map
  // (random in vertex order) does not. The gather of A_II from A (one-shot
  // path) still uses the map.
  int32_t local_of(int32_t v) const {
    const size_t wi = static_cast<size_t>(v) >> 6;
    return u.vrank_[wi] + std::popcount(u.vbits_[wi] & ((uint64_t{1} << (v & 63)) - 1));
  }

  FactorUpdater& u;
  const NumericFactor& L;
  const SymbolicFactor& S;  // L's
  const FactorUpdateOptions& opt;
  const std::span<const int32_t> I;
  const RunContext& ctx;
  const bool two_threads;  // see update_impl
  const bool prepared;     // index_rows: row index and A in factor order
  const bool borrow;       // sharing form
  const clock::time_point t0 = clock::now();
  FactorUpdate out;
  FactorUpdateStats& st = out.stats;
  int32_t m = 0;              // |I|
  std::vector<int32_t> gcol;  // I's factor columns, ascending
  bool cbits_clear = false;   // cbits_ cleared from gcol already (sequential, unlike iperm of I)
  bool maps_filled = false;   // col_new_ and in_super_ were set for gcol
  update_detail::Restricted R;          // the restricted structure, with positions in L's blocks
  std::shared_ptr<SymbolicFactor> Sp;   // the result's symbolic factor
  std::vector<uint8_t> cmark, smark;    // marked columns / supernodes of Sp
};

}  // namespace locus
