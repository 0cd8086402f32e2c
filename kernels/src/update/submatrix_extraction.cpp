// A_II for the factor-once update (declared in submatrix_extraction.hpp) and
// the public principal_submatrix (kernels/include/locus/kernels/update/factor_update.hpp;
// thesis §5.4).
#include "submatrix_extraction.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/core/bit_set.hpp"
#include "locus/kernels/update/factor_update.hpp"

namespace locus {
namespace update_detail {

void fail_not_finite(std::span<const int32_t> vertices, std::span<const int32_t> ids, int32_t a, int32_t b) {
  auto nm = [&](int32_t x) { return std::to_string(ids.empty() ? vertices[x] : ids[vertices[x]]); };
  throw NotFiniteEntry(ErrorCode::Numerical, "submatrix entry of vertices " + nm(a) + " and " + nm(b) + " is not finite");
}

void assemble_from_factor_order(SymbolicFactor& Sp, const std::vector<int32_t>& gcol, const std::vector<int32_t>& col_new,
                                const std::vector<int64_t>& ap_ptr, const std::vector<int32_t>& ap_row,
                                const std::vector<double>& ap_val, const std::vector<int32_t>& vertices,
                                std::span<const int32_t> ids, CscMatrix& B) {
  const int32_t m = Sp.n, ns = Sp.ns;
  int64_t bound = 0;
  for (int32_t c = 0; c < m; ++c) bound += ap_ptr[gcol[c] + 1] - ap_ptr[gcol[c]];
  // One record per entry (local column and row, row >= column, and value):
  // the sort by column below fetches an entry with one cache miss, not three.
  // Scratch arrays are left uninitialized: every slot read is written first.
  struct Entry {
    int32_t col, row;
    double val;
  };
  std::vector<Entry, DefaultInitAllocator<Entry>> e(static_cast<size_t>(bound));
  Sp.a_super_ptr.assign(static_cast<size_t>(ns) + 1, 0);
  Sp.a_dst.resize(static_cast<size_t>(bound));
  std::vector<int32_t> rowpos(m);
  bool finite = true;
  int64_t k = 0;
  for (int32_t s = 0; s < ns; ++s) {
    const int32_t f = Sp.super_first_col[s], l = Sp.super_first_col[s + 1], nr = Sp.nrows(s);
    const int32_t* rows = Sp.super_rows.data() + Sp.super_row_ptr[s];
    for (int32_t t = 0; t < nr; ++t) rowpos[rows[t]] = t;
    for (int32_t c = f; c < l; ++c) {
      const int32_t gc = gcol[c], b = Sp.perm[c];
      const int64_t col_off = Sp.super_value_ptr[s] + static_cast<int64_t>(c - f) * nr;
      for (int64_t p = ap_ptr[gc]; p < ap_ptr[gc + 1]; ++p) {
        const int32_t r = col_new[ap_row[p]];
        if (r < 0) continue;
        const int32_t t = rowpos[r];
        if (r < c || t < 0 || t >= nr || rows[t] != r)
          fail(ErrorCode::Internal, "factor update: restricted structure misses entry (" + std::to_string(r) + ", " +
                                        std::to_string(c) + ") of the submatrix");
        const int32_t a = Sp.perm[r];
        const double v = ap_val[p];
        Sp.a_dst[static_cast<size_t>(k)] = col_off + t;
        e[static_cast<size_t>(k)] = Entry{std::min(a, b), std::max(a, b), v};
        finite = finite && std::isfinite(v);
        ++k;
      }
    }
    Sp.a_super_ptr[s + 1] = k;
  }
  Sp.a_dst.resize(static_cast<size_t>(k));
  if (!finite)
    for (int64_t q = 0; q < k; ++q)
      if (!std::isfinite(e[q].val)) fail_not_finite(vertices, ids, e[q].row, e[q].col);
  // A_II's columns, rows ascending: a counting sort by row, then a stable one
  // by column; a_src follows the entries.
  std::vector<int32_t, DefaultInitAllocator<int32_t>> by_row(static_cast<size_t>(k));
  {
    std::vector<int32_t> cnt(static_cast<size_t>(m) + 1, 0);
    for (int64_t q = 0; q < k; ++q) ++cnt[e[q].row + 1];
    for (int32_t a = 0; a < m; ++a) cnt[a + 1] += cnt[a];
    for (int64_t q = 0; q < k; ++q) by_row[cnt[e[q].row]++] = static_cast<int32_t>(q);
  }
  B.nrows = B.ncols = m;
  B.colptr.assign(static_cast<size_t>(m) + 1, 0);
  for (int64_t q = 0; q < k; ++q) ++B.colptr[e[q].col + 1];
  for (int32_t a = 0; a < m; ++a) B.colptr[a + 1] += B.colptr[a];
  B.rowind.resize(static_cast<size_t>(k));
  B.values.resize(static_cast<size_t>(k));
  Sp.a_src.resize(static_cast<size_t>(k));
  std::vector<int64_t> next(B.colptr.begin(), B.colptr.end() - 1);
  for (const int32_t q : by_row) {
    const Entry& x = e[q];
    const int64_t dst = next[x.col]++;
    B.rowind[dst] = x.row;
    B.values[dst] = x.val;
    Sp.a_src[q] = dst;
  }
  Sp.a_nnz = k;
  Sp.a_pattern_hash = pattern_hash(B);
}

}  // namespace update_detail

CscMatrix principal_submatrix(const CscMatrix& A, std::span<const int32_t> vertices) {
  const int32_t n = A.ncols;
  std::vector<int32_t> local(n, -1);
  int32_t prev = -1;
  for (size_t a = 0; a < vertices.size(); ++a) {
    const int32_t v = vertices[a];
    if (v < 0 || v >= n || v <= prev)
      fail(ErrorCode::BadUsage, "principal_submatrix: indices must be sorted, unique and in [0, " + std::to_string(n) +
                                    "); entry " + std::to_string(a) + " is " + std::to_string(v));
    local[v] = static_cast<int32_t>(a);
    prev = v;
  }
  return update_detail::submatrix_from_map(A, vertices, local);
}

}  // namespace locus
