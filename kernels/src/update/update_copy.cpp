// Step (3) of the factor-once update (thesis §5.5): the unmarked supernodes of
// the result are L_II's columns, copied from L's blocks (their kept rows), or,
// in the sharing form, borrowed when they are whole global blocks.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "factor_update_call.hpp"

namespace locus {

using update_detail::in_arena;

// Sharing form: an unmarked supernode that keeps every row and column of its
// global supernode has exactly that block (same rows, same order, same values):
// borrow it. The others (recomputed, or restricted) are own blocks.
void FactorUpdater::Call::lay_out_borrowed() {
  NumericFactor& F = out.factor;
  F.borrowed.assign(Sp->ns, nullptr);
  F.own_offset.assign(Sp->ns, -1);
  int64_t own = 0;
  for (int32_t s = 0; s < Sp->ns; ++s) {
    const int32_t gs = R.gsuper[s];
    const int64_t size = Sp->super_value_ptr[s + 1] - Sp->super_value_ptr[s];
    if (!smark[s] && Sp->ncols(s) == S.ncols(gs) && Sp->nrows(s) == S.nrows(gs)) {
      F.borrowed[s] = L.block(gs);
      st.values_borrowed += size;
    } else {
      F.own_offset[s] = own;
      own += size;
    }
  }
  F.values.resize(static_cast<size_t>(own));
  F.lender = u.lender_;
}

// (3) Copies the unmarked, not borrowed supernodes' restricted blocks from L.
// Threads only pay off for large copies (a gather, memory-bound), except in the
// prepared two-thread update: there the other thread extracts A_II meanwhile
// and takes over part of the copy once it is done (work stealing; each
// supernode is copied by one thread, so the result is the same).
void FactorUpdater::Call::copy_unmarked() {
  const int64_t copied = st.values_stored - st.values_recomputed - st.values_borrowed;
  const bool steal = two_threads && copied >= (int64_t{1} << 16);
  if (!steal && copied < (int64_t{1} << 22)) {
    copy_supernodes(0, Sp->ns);
  } else {
    in_arena(ctx, [&](int) {
      tbb::parallel_for(tbb::blocked_range<int32_t>(0, Sp->ns, 64),
                        [&](const tbb::blocked_range<int32_t>& rg) { copy_supernodes(rg.begin(), rg.end()); });
    });
  }
}

void FactorUpdater::Call::copy_supernodes(int32_t s0, int32_t s1) {
  NumericFactor& F = out.factor;
  for (int32_t s = s0; s < s1; ++s) {
    if (smark[s] || (borrow && F.borrowed[s])) continue;
    const int32_t gs = R.gsuper[s];
    const int64_t gm = S.nrows(gs);
    const double* src = L.block(gs);
    double* dst = F.block(s);
    const int32_t k = Sp->ncols(s), mr = Sp->nrows(s), f = Sp->super_first_col[s];
    const int32_t* rp = R.rowpos.data() + R.row_ptr[s];
    // Kept rows that are one run of the global rows (a supernode inside the
    // patch) are copied as runs, the others gathered.
    const bool run = rp[mr - 1] - rp[0] == mr - 1;
    for (int32_t j = 0; j < k; ++j) {
      const double* sc = src + static_cast<int64_t>(R.colpos[f + j]) * gm;
      double* dc = dst + static_cast<int64_t>(j) * mr;
      for (int32_t t = 0; t < j; ++t) dc[t] = 0.0;  // unused upper triangle, kept defined
      if (run) {
        const double* sr = sc + rp[0];
        for (int32_t t = j; t < mr; ++t) dc[t] = sr[t];
      } else {
        for (int32_t t = j; t < mr; ++t) dc[t] = sc[rp[t]];
      }
    }
  }
}

}  // namespace locus
