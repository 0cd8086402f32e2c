// Step (2) of the factor-once update (thesis §5.5, Figure 5.5c–e): marking the
// columns of the restricted structure whose values differ from L_II's, the
// ancestors of the first I-row of every column of L_IB; and the work the marks
// imply.
#include "factor_update_call.hpp"

namespace locus {

// Marks the etree path from restricted column c up to the first marked column.
void FactorUpdater::Call::walk(int32_t c) {
  for (; c >= 0 && !cmark[c]; c = Sp->parent[c]) {
    cmark[c] = 1;
    ++st.columns_marked;
    smark[Sp->col_to_super[c]] = 1;
  }
}

// (2) Marking (§5.5): the changed columns are the ancestors, in the restricted
// etree, of the first I-row of every column of L_IB. All I-rows of a column lie
// on one etree path, so starting from every I-row of a B column marks the same
// set, and those rows are found from the I side in time that depends on I: an I
// column is such a row when a B column precedes it in its own supernode, or
// when a supernode with a B column has it among its rows below the diagonal
// block (below_super_ lists those per row).
void FactorUpdater::Call::mark_changed() {
  const std::vector<int32_t>& col_new = u.col_new_;
  cmark.assign(m, 0);
  smark.assign(Sp->ns, 0);
  for (size_t q = 0; q < gcol.size();) {
    const int32_t s = S.col_to_super[gcol[q]];
    const int32_t f = S.super_first_col[s], l = S.super_first_col[s + 1];
    size_t q2 = q;
    while (q2 < gcol.size() && gcol[q2] < l) ++q2;
    for (size_t t = q; t < q2; ++t)
      if (gcol[t] - f > static_cast<int32_t>(t - q)) {  // fewer I columns than positions before it: a B column
        walk(col_new[gcol[t]]);
        break;  // the later columns of s are its ancestors
      }
    q = q2;
  }
  if (u.below_ptr_.empty()) {
    // Without the row index (one-shot updates): scan the rows of every global
    // supernode with a B column for its first I-row — O(structure of L), still
    // cheaper than building the index for a single update.
    for (int32_t s = 0; s < S.ns; ++s) {
      if (u.in_super_[s] == S.ncols(s)) continue;  // no column of s is in B
      const int64_t r0 = S.super_row_ptr[s] + S.ncols(s);
      for (int64_t t = r0; t < S.super_row_ptr[s + 1]; ++t)
        if (col_new[S.super_rows[t]] >= 0) {
          walk(col_new[S.super_rows[t]]);
          break;  // its later I-rows are ancestors of this one
        }
    }
  }
  for (const int32_t c : gcol) {
    if (u.below_ptr_.empty() || cmark[col_new[c]]) continue;
    for (int64_t p = u.below_ptr_[c]; p < u.below_ptr_[c + 1]; ++p) {
      const int32_t d = u.below_super_[p];
      if (u.in_super_[d] < S.ncols(d)) {
        walk(col_new[c]);
        break;
      }
    }
  }
}

// The work the marks imply (FactorUpdateStats).
void FactorUpdater::Call::count_marked() {
  for (int32_t s = 0; s < Sp->ns; ++s)
    if (smark[s]) {
      ++st.supernodes_recomputed;
      st.columns_recomputed += Sp->ncols(s);
      st.values_recomputed += Sp->super_value_ptr[s + 1] - Sp->super_value_ptr[s];
      st.flops_recomputed += Sp->flops(s);
    }
  st.columns_updated_fraction = static_cast<double>(st.columns_recomputed) / m;
}

}  // namespace locus
