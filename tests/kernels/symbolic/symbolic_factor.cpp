// Tests for kernels/symbolic_factor, etree, column_counts, supernodes:
// against a brute-force symbolic elimination on a dense boolean pattern, and
// (the parallel analysis over subtrees) against Eigen's
// SimplicialLLT and across thread counts and subtree partitions.
#include "locus/kernels/symbolic/symbolic_factor.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <string_view>
#include <random>
#include <set>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/assembly_map.hpp"
#include "locus/kernels/symbolic/column_counts.hpp"
#include "locus/kernels/symbolic/etree.hpp"
#include "locus/kernels/symbolic/permuted_graph.hpp"
#include "locus/kernels/symbolic/subtree_partition.hpp"
#include "locus/kernels/symbolic/supernode_rows.hpp"
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

namespace {

// A subtree partition's contract: disjoint ascending pieces of whole
// subtrees within the bound, every other node top with top ancestors.
void check_partition(std::span<const int32_t> parent, const SubtreePartition& P, int64_t bound, std::span<const int64_t> w) {
  const int32_t n = static_cast<int32_t>(parent.size());
  std::vector<int32_t> where(n, -2);  // piece, or -1 = top
  for (int32_t q = 0; q < P.num_pieces(); ++q) {
    REQUIRE(P.piece_begin[q] < P.piece_end[q]);
    if (q > 0) REQUIRE(P.piece_end[q - 1] <= P.piece_begin[q]);
    int64_t weight = 0;
    for (int32_t j = P.piece_begin[q]; j < P.piece_end[q]; ++j) {
      where[j] = q;
      weight += w[j];
    }
    CHECK(weight <= bound);
  }
  for (int32_t t : P.top) {
    REQUIRE(where[t] == -2);
    where[t] = -1;
  }
  for (int32_t j = 0; j < n; ++j) {
    REQUIRE(where[j] != -2);
    const int32_t p = parent[j];
    if (p < 0) continue;
    if (where[j] == -1) CHECK(where[p] == -1);              // above a top node: top
    else CHECK((where[p] == where[j] || where[p] == -1));  // a piece's parents: inside or top
  }
}

// Every array of two symbolic factors.
void check_same(const SymbolicFactor& a, const SymbolicFactor& b) {
  CHECK(a.n == b.n);
  CHECK(a.perm == b.perm);
  CHECK(a.iperm == b.iperm);
  CHECK(a.parent == b.parent);
  CHECK(a.col_count == b.col_count);
  CHECK(a.nnz_exact == b.nnz_exact);
  CHECK(a.etree_height == b.etree_height);
  CHECK(a.ns == b.ns);
  CHECK(a.super_first_col == b.super_first_col);
  CHECK(a.col_to_super == b.col_to_super);
  CHECK(a.super_parent == b.super_parent);
  CHECK(a.super_row_ptr == b.super_row_ptr);
  CHECK(a.super_rows == b.super_rows);
  CHECK(a.super_value_ptr == b.super_value_ptr);
  CHECK(a.nnz_L == b.nnz_L);
  CHECK(a.super_etree_height == b.super_etree_height);
  CHECK(a.a_super_ptr == b.a_super_ptr);
  CHECK(a.a_src == b.a_src);
  CHECK(a.a_dst == b.a_dst);
  CHECK(a.a_pattern_hash == b.a_pattern_hash);
  CHECK(a.a_nnz == b.a_nnz);
  CHECK(a.max_update_entries == b.max_update_entries);
  CHECK(a.max_super_rows == b.max_super_rows);
  CHECK(a.update_ptr == b.update_ptr);
  CHECK(a.update_from == b.update_from);
}

HostVector<int64_t> unit_weights(size_t n) { return HostVector<int64_t>(n, 1); }

}  // namespace

TEST_CASE("subtree partitions: column counts and row structures of every partition and graph chunking match brute force") {
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    CAPTURE(seed);
    const int32_t n = 30 + static_cast<int32_t>(seed * 37 % 170);
    const CscMatrix A = seed % 3 == 0 ? test::grid_laplacian(7, 5 + static_cast<int>(seed), 0.1)
                                      : test::random_spd(n, 1 + static_cast<int>(seed % 5), seed);
    OrderingOptions oo;
    if (seed % 2 == 0) oo.method = OrderingOptions::Method::NestedDissection;
    const auto S = analyze(A, order_matrix(A, oo));
    const BruteSymbolic b = brute_force(A, S->iperm);
    REQUIRE(S->col_count == b.count);
    HalfGraph g1, g;
    permuted_half_graph(A, S->iperm, Half::Above, 1, g1);
    for (int chunks : {2, 3, 7}) {  // the same graph and assembly map for every chunk count
      permuted_half_graph(A, S->iperm, Half::Above, chunks, g);
      CHECK(g.ptr == g1.ptr);
      CHECK(g.idx == g1.idx);
      SymbolicFactor T = *S;
      T.a_src.assign(T.a_src.size(), -1);
      T.a_dst.assign(T.a_dst.size(), -1);
      assembly_map(T, A, chunks);
      CHECK(T.a_super_ptr == S->a_super_ptr);
      CHECK(T.a_src == S->a_src);
      CHECK(T.a_dst == S->a_dst);
    }
    // The assembly map against the brute-force pattern: every entry of A
    // lands at its own (row, column) of L, in its column's supernode.
    for (int32_t s = 0; s < S->ns; ++s)
      for (int64_t k = S->a_super_ptr[s]; k < S->a_super_ptr[s + 1]; ++k) {
        const int64_t off = S->a_dst[k] - S->super_value_ptr[s];
        const int32_t c = S->super_first_col[s] + static_cast<int32_t>(off / S->nrows(s));
        const int32_t r = S->super_rows[S->super_row_ptr[s] + off % S->nrows(s)];
        const int64_t p = S->a_src[k];
        const int32_t j = static_cast<int32_t>(std::upper_bound(A.colptr.begin(), A.colptr.end(), p) - A.colptr.begin()) - 1;
        const int32_t a = S->iperm[A.rowind[p]], bb = S->iperm[j];
        CHECK(r == std::max(a, bb));
        CHECK(c == std::min(a, bb));
        if (k > S->a_super_ptr[s]) CHECK(S->a_src[k - 1] < p);  // ascending in A within a group
      }
    for (int64_t bound : {int64_t{1}, int64_t{2}, int64_t{5}, int64_t{17}, int64_t{A.ncols / 3}, int64_t{A.ncols}}) {
      CAPTURE(bound);
      const SubtreePartition P = subtree_partition(S->parent, unit_weights(S->n), bound);
      check_partition(S->parent, P, bound, unit_weights(S->n));
      CHECK(column_counts_postordered(S->n, g.ptr, g.idx, S->parent, P) == b.count);
      const SubtreePartition Q = subtree_partition(S->super_parent, unit_weights(S->ns), bound);
      check_partition(S->super_parent, Q, bound, unit_weights(S->ns));
      SymbolicFactor T = *S;
      T.super_rows.assign(T.super_rows.size(), -7);
      supernode_rows(T, g.ptr, g.idx, Q);
      CHECK(T.super_row_ptr == S->super_row_ptr);
      CHECK(T.super_rows == S->super_rows);  // checked against brute force by the tests above
    }
  }
}

TEST_CASE("symbolic analysis: every array identical at 1/2/3/8 threads and column counts as Eigen's (icosphere 41k)") {
  const Mesh m = make_icosphere(6);  // 40962 vertices: above the size where the analysis goes parallel
  const CscMatrix A = heat_operator(m, 1e-4);
  for (auto method : {OrderingOptions::Method::NestedDissection, OrderingOptions::Method::Amd}) {
    OrderingOptions oo;
    oo.method = method;
    const Ordering o = order_matrix(A, oo);
    RunContext one;
    one.threads = 1;
    const auto S1 = analyze(A, o, {}, one);
    // The partitions two threads use split the tree (else this test could not fail).
    const SubtreePartition P = subtree_partition(S1->parent, unit_weights(S1->n), S1->n / 8);
    CHECK(P.num_pieces() >= 4);
    CHECK(!P.top.empty());
    // Column counts against Eigen's factor of P A P^T (its own symbolic analysis).
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm(A.ncols);
    for (int32_t k = 0; k < A.ncols; ++k) perm.indices()[S1->perm[k]] = k;
    const Eigen::SparseMatrix<double> E = test::to_eigen(A);
    const Eigen::SparseMatrix<double> PE = (perm * E * perm.transpose()).eval();
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt(PE);
    REQUIRE(llt.info() == Eigen::Success);
    const Eigen::SparseMatrix<double> L = llt.matrixL();
    CHECK(L.nonZeros() == S1->nnz_exact);
    int32_t differ = 0;
    for (int32_t j = 0; j < A.ncols; ++j) differ += L.col(j).nonZeros() != S1->col_count[j];
    CHECK(differ == 0);
    CHECK_NOTHROW(validate_symbolic(*S1, -1));
    for (int threads : {2, 3, 8}) {
      CAPTURE(threads);
      RunContext ctx;
      ctx.threads = threads;
      check_same(*S1, *analyze(A, o, {}, ctx));
    }
    // Progress reaches the caller, and a cancel raised from it stops the parallel analysis.
    std::atomic<bool> cancel{false};
    RunContext ctx;
    ctx.threads = 2;
    ctx.cancel = &cancel;
    int reports = 0;
    ctx.progress = [&](double, std::string_view) {
      ++reports;
      cancel = true;
    };
    ErrorCode code = ErrorCode::Internal;
    try {
      (void)analyze(A, o, {}, ctx);
    } catch (const Error& e) {
      code = e.code();
    }
    CHECK(reports >= 1);
    CHECK(code == ErrorCode::Cancelled);
  }
}

TEST_CASE("a released assembly map: solves still work, factorizing again is refused") {
  const CscMatrix A = test::grid_laplacian(12, 10, 0.1);
  auto S = std::const_pointer_cast<SymbolicFactor>(analyze(A, order_matrix(A)));
  const NumericFactor F = factorize(S, A);
  std::vector<double> before(static_cast<size_t>(A.ncols), 1.0), after = before;
  solve(F, before);
  release_assembly_map(*S);
  CHECK(S->a_src.capacity() == 0);
  CHECK(S->a_dst.capacity() == 0);
  CHECK(S->parent.capacity() == 0);
  CHECK(S->col_count.capacity() == 0);
  solve(F, after);
  CHECK(after == before);
  CHECK_THROWS_AS(factorize(S, A), Error);
  NumericFactor G = F;
  CHECK_THROWS_AS(refactorize(G, A), Error);
}
