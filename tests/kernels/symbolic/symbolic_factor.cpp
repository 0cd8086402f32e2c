// Tests for kernels/symbolic_factor, etree, column_counts, supernodes:
// against a brute-force symbolic elimination on a dense boolean pattern.
#include "locus/kernels/symbolic/symbolic_factor.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include "locus/kernels/symbolic/etree.hpp"
#include "locus/error.hpp"
#include "locus/view.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

struct BruteSymbolic {
  std::vector<int32_t> parent, count;
  std::vector<std::vector<char>> pattern;  // pattern[i][j], i >= j
};

// Symbolic elimination of P A P^T with perm (factor numbering).
BruteSymbolic brute_force(const CscMatrix& A, ConstView<int32_t> iperm) {
  const int32_t n = A.ncols;
  std::vector<std::vector<char>> B(n, std::vector<char>(n, 0));
  for (int32_t j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t a = iperm[A.rowind[p]], b = iperm[j];
      B[a][b] = B[b][a] = 1;
    }
  BruteSymbolic r;
  r.parent.assign(n, -1);
  r.count.assign(n, 1);
  for (int32_t k = 0; k < n; ++k) {
    B[k][k] = 1;
    std::vector<int32_t> below;
    for (int32_t i = k + 1; i < n; ++i)
      if (B[i][k]) below.push_back(i);
    r.count[k] += static_cast<int32_t>(below.size());
    if (!below.empty()) r.parent[k] = below.front();
    for (int32_t i : below)
      for (int32_t j : below) B[i][j] = 1;
  }
  r.pattern = B;
  return r;
}

void check_against_brute_force(const CscMatrix& A, const OrderingOptions& oo, const SymbolicOptions& so = {}) {
  const Ordering o = order_matrix(A, oo);
  auto S = analyze(A, o, so);
  const int32_t n = A.ncols;
  REQUIRE(S->n == n);
  // perm is a permutation and iperm its inverse.
  for (int32_t k = 0; k < n; ++k) REQUIRE(S->iperm[S->perm[k]] == k);
  const BruteSymbolic b = brute_force(A, S->iperm);
  CHECK(S->parent == b.parent);
  CHECK(S->col_count == b.count);
  int64_t nnz = 0;
  for (int32_t c : b.count) nnz += c;
  CHECK(S->nnz_exact == nnz);
  CHECK(S->nnz_L >= nnz);
  // Postorder: every etree subtree is a contiguous range ending at its root.
  std::vector<int32_t> first(n);
  for (int32_t j = 0; j < n; ++j) first[j] = j;
  for (int32_t j = 0; j < n; ++j)
    if (S->parent[j] >= 0) {
      CHECK(S->parent[j] > j);
      first[S->parent[j]] = std::min(first[S->parent[j]], first[j]);
    }
  std::vector<int32_t> size(n, 1);
  for (int32_t j = 0; j < n; ++j)
    if (S->parent[j] >= 0) size[S->parent[j]] += size[j];
  for (int32_t j = 0; j < n; ++j) CHECK(j - first[j] + 1 == size[j]);
  // Supernodes: contiguous, parent after child, rows sorted, own columns first,
  // and every true nonzero of L inside its supernode's stored rows.
  REQUIRE(S->super_first_col.front() == 0);
  REQUIRE(S->super_first_col.back() == n);
  for (int32_t s = 0; s < S->ns; ++s) {
    CHECK(S->ncols(s) >= 1);
    if (S->super_parent[s] >= 0) CHECK(S->super_parent[s] > s);
    const int32_t* rows = S->super_rows.data() + S->super_row_ptr[s];
    for (int32_t t = 0; t < S->ncols(s); ++t) CHECK(rows[t] == S->super_first_col[s] + t);
    for (int32_t t = 1; t < S->nrows(s); ++t) CHECK(rows[t] > rows[t - 1]);
    std::set<int32_t> rowset(rows, rows + S->nrows(s));
    for (int32_t c = S->super_first_col[s]; c < S->super_first_col[s + 1]; ++c)
      for (int32_t i = c; i < n; ++i)
        if (b.pattern[i][c]) CHECK(rowset.count(i) == 1);
  }
  // Row structure is the transpose of the supernodal column structure.
  const RowStructure R = row_structure(*S);
  int64_t entries = 0;
  for (int32_t s = 0; s < S->ns; ++s)
    for (int32_t c = S->super_first_col[s]; c < S->super_first_col[s + 1]; ++c)
      for (int64_t p = S->super_row_ptr[s] + (c - S->super_first_col[s]) + 1; p < S->super_row_ptr[s + 1]; ++p) {
        const int32_t r = S->super_rows[p];
        CHECK(std::binary_search(R.cols.begin() + R.row_ptr[r], R.cols.begin() + R.row_ptr[r + 1], c));
        ++entries;
      }
  CHECK(entries == static_cast<int64_t>(R.cols.size()));
  CHECK(S->etree_height == tree_height(S->parent));
  CHECK(S->etree_height >= 1);
}

}  // namespace

TEST_CASE("symbolic analysis matches brute-force elimination: grids") {
  for (int nx : {1, 2, 5, 12}) {
    CAPTURE(nx);
    check_against_brute_force(test::grid_laplacian(nx, nx + 3, 0.1), {});
    OrderingOptions natural;
    natural.method = OrderingOptions::Method::Natural;
    check_against_brute_force(test::grid_laplacian(nx, nx + 3, 0.1), natural);
  }
}

TEST_CASE("symbolic analysis matches brute-force elimination: random sparse SPD") {
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    CAPTURE(seed);
    const int32_t n = 20 + static_cast<int32_t>(seed * 17 % 150);
    check_against_brute_force(test::random_spd(n, 1 + static_cast<int>(seed % 6), seed), {});
  }
  // No amalgamation at all: fundamental supernodes only.
  SymbolicOptions fundamental;
  fundamental.relax_cols_small = 0;
  fundamental.relax_cols_medium = 0;
  fundamental.relax_cols_large = 0;
  fundamental.relax_zeros_huge = -1;
  check_against_brute_force(test::random_spd(120, 4, 99), {}, fundamental);
}

TEST_CASE("symbolic analysis: the third-party SPD suite") {
  for (const char* f : {"bcsstk01.tri", "bcsstk02.tri", "pts5ldd03.mtx", "two.tri"}) {
    CAPTURE(f);
    check_against_brute_force(test::read_triplet_file(std::string(LOCUS_TEST_DATA_DIR) + "/" + f), {});
  }
}

TEST_CASE("symbolic analysis rejects malformed input") {
  CscMatrix A = test::grid_laplacian(3, 3, 1.0);
  Ordering o = order_matrix(A);
  CscMatrix B = A;
  B.nrows = 8;
  CHECK_THROWS_AS(analyze(B, o), Error);
  Ordering bad = o;
  bad.perm[0] = bad.perm[1];
  CHECK_THROWS_AS(analyze(A, bad), Error);
  CscMatrix U = A;  // an upper-triangle entry
  U.rowind[U.colptr[1]] = 0;
  CHECK_THROWS_AS(analyze(U, o), Error);
}

TEST_CASE("empty and 1x1 matrices") {
  CscMatrix E;
  auto S0 = analyze(E, order_matrix(E));
  CHECK(S0->n == 0);
  CHECK(S0->ns == 0);
  CscMatrix one = lower_from_triplets(1, {0}, {0}, {4.0});
  auto S1 = analyze(one, order_matrix(one));
  CHECK(S1->ns == 1);
  CHECK(S1->nnz_L == 1);
}
