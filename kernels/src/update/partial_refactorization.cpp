// Step (4) of the factor-once update (thesis §5.5): the marked supernodes
// recomputed by the left-looking supernodal factorization (factorize_supernodes),
// assembled from A_II or, in the prepared updater, straight from A in factor
// order; and the fresh factorization of a scattered set, where the restricted
// structure would hold far more fill than A_II's own factor. A failed pivot is
// reported naming the vertex in A's numbering.
#include <algorithm>
#include <cmath>
#include <string>

#include "factor_update_call.hpp"
#include "locus/error.hpp"
#include "submatrix_extraction.hpp"

namespace locus {

using update_detail::fail_not_finite;
using update_detail::NotFiniteEntry;
using update_detail::seconds_since;
using update_detail::submatrix_with;

namespace {

// Re-raises a not-positive-definite error of the submatrix factorization with
// the vertex named in A's numbering (or the caller's ids), not the local one.
[[noreturn]] void rethrow_numerical(const Error& e, const SymbolicFactor& Sp, std::span<const int32_t> vertices,
                                    std::span<const int32_t> ids) {
  const std::string msg = e.what();
  const int64_t col = e.where().column;
  if (col >= 0 && col < Sp.n) {
    const int32_t local = Sp.perm[static_cast<size_t>(col)];
    const int32_t v = vertices[local];
    const int32_t name = ids.empty() ? v : ids[v];
    fail(ErrorCode::Numerical,
         "submatrix is not positive definite at vertex " + std::to_string(name) + " (submatrix index " +
             std::to_string(local) + ", factor column " + std::to_string(col) + ")",
         ErrorLocation{name, col});
  }
  fail(ErrorCode::Numerical, std::string("submatrix: ") + msg);
}

}  // namespace

// Runs a factorization of A_II. A numerical failure (a pivot) is re-raised
// naming the vertex in A's numbering; a non-finite entry (NotFiniteEntry, from
// the direct assembler) names its vertices already and passes unchanged.
template <class Factorize>
void FactorUpdater::Call::factor_naming_vertices(const SymbolicFactor& Sf, Factorize&& run) {
  try {
    run();
  } catch (const NotFiniteEntry&) {
    throw;
  } catch (const Error& e) {
    if (e.code() != ErrorCode::Numerical) throw;
    rethrow_numerical(e, Sf, out.vertices, opt.vertex_ids);
  }
}

// A scattered set (touched_share below refactor_below_share): A_II analysed and
// factored from scratch, in L's relative order (I's factor columns ascending).
// Membership and rank come from the bit set (n/64 words, in cache), not the
// n-sized map; the column map and per-supernode counts are never filled.
void FactorUpdater::Call::refactor_fresh() {
  out.A_sub = submatrix_with(u.A_, out.vertices, [&](int32_t v) {
    return (u.vbits_[static_cast<size_t>(v) >> 6] >> (v & 63)) & 1 ? local_of(v) : -1;
  });
  for (int32_t a = 0; a < m; ++a)
    for (int64_t p = out.A_sub.colptr[a]; p < out.A_sub.colptr[a + 1]; ++p)
      if (!std::isfinite(out.A_sub.values[p])) fail_not_finite(out.vertices, opt.vertex_ids, out.A_sub.rowind[p], a);
  Ordering order;
  order.perm.resize(m);
  order.iperm.resize(m);
  for (int32_t c = 0; c < m; ++c) {
    order.perm[c] = local_of(S.perm[gcol[c]]);
    order.iperm[order.perm[c]] = c;
  }
  auto Sx = analyze(out.A_sub, order);
  st.structure_s = seconds_since(t0);
  const auto t3 = clock::now();
  factor_naming_vertices(*Sx, [&] { out.factor = factorize(Sx, out.A_sub, ctx); });
  st.factor_s = seconds_since(t3);
  st.refactored = true;
  st.supernodes = st.supernodes_recomputed = Sx->ns;
  st.columns_marked = st.columns_recomputed = m;
  st.columns_updated_fraction = 1.0;
  st.values_stored = st.values_recomputed = Sx->super_value_ptr[Sx->ns];
  st.nnz_stored = Sx->nnz_L;
  st.flops_recomputed = Sx->flops();
}

// Prepared updater: columns [c0, c1) of marked supernode s assembled from the
// copy of A in factor order (a SupernodeAssembler).
void FactorUpdater::Call::assemble_direct(int32_t s, int32_t c0, int32_t c1, double* block,
                                          const int32_t* rowmap) const {
  const int32_t f = Sp->super_first_col[s], nr = Sp->nrows(s);
  for (int32_t c = f + c0; c < f + c1; ++c) {
    const int32_t gc = R.gcol[c];
    double* col = block + static_cast<int64_t>(c - f) * nr;
    for (int64_t p = u.ap_ptr_[gc]; p < u.ap_ptr_[gc + 1]; ++p) {
      const int32_t r = u.col_new_[u.ap_row_[p]];
      if (r < 0) continue;
      const double v = u.ap_val_[p];
      if (!std::isfinite(v)) {  // as A_II's extraction reports it (whichever comes first)
        const int32_t a = Sp->perm[r], b = Sp->perm[c];
        fail_not_finite(out.vertices, opt.vertex_ids, std::max(a, b), std::min(a, b));
      }
      col[rowmap[r]] = v;
    }
  }
}

// (4) Recomputes the marked supernodes (left-looking, skipping the others),
// assembled by `direct` (prepared) or from A_II (one-shot).
void FactorUpdater::Call::refactor_marked(const SupernodeAssembler* direct) {
  const auto t3 = clock::now();
  if (st.supernodes_recomputed > 0)
    factor_naming_vertices(*Sp, [&] {
      if (direct) factorize_supernodes_assembled(out.factor, smark, *direct, ctx);
      else factorize_supernodes(out.factor, out.A_sub, smark, ctx);
    });
  st.factor_s = seconds_since(t3);
}

}  // namespace locus
