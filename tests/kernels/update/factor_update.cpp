// Tests for the factor-once update, kernels/src/update/
// (thesis chapter 5): the updated factor L' of A_II against independent
// oracles — the residual of A_II x = b with A_II assembled here from A by hand; entry-by-entry equality with a from-scratch
// locus factorization of A_II in the same elimination order (the Cholesky factor
// is unique; entries are compared by vertex pair since a postorder of the
// elimination tree may move columns); an Eigen SimplicialLLT solve of A_II.
// Operators: -L_C + eps M and the bi-Laplacian K M^{-1} K (built with Eigen).
// Sets: BFS patches of 10/25/50%, scattered random sets, single vertex, all
// vertices, two components, a 2-step cascade; bad sets; a non-positive pivot;
// non-finite entries (also one met inside the recomputation).
#include "locus/kernels/update/factor_update.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <typeinfo>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "tests/kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

using SpMat = Eigen::SparseMatrix<double>;

// Bi-Laplacian K M^{-1} K with K = -L_C + eps M, by Eigen sparse products.
CscMatrix bilaplacian(const Mesh& m, double rel) {
  const SpMat K = test::to_eigen(regularized_laplacian(m, rel));
  const auto M = lumped_mass(m);
  Eigen::VectorXd minv(static_cast<Eigen::Index>(M.size()));
  for (size_t i = 0; i < M.size(); ++i) minv[static_cast<Eigen::Index>(i)] = 1.0 / M[i];
  const SpMat B = (K * minv.asDiagonal() * K).pruned();
  return test::from_eigen_lower(B);
}

// A_II assembled directly from A's entries (independent of principal_submatrix).
SpMat submatrix_by_hand(const CscMatrix& A, const std::vector<int32_t>& sorted) {
  std::vector<int32_t> pos(A.ncols, -1);
  for (size_t a = 0; a < sorted.size(); ++a) pos[sorted[a]] = static_cast<int32_t>(a);
  std::vector<Eigen::Triplet<double>> t;
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      const int32_t i = A.rowind[p];
      if (pos[i] < 0 || pos[j] < 0) continue;
      t.emplace_back(pos[i], pos[j], A.values[p]);
      if (i != j) t.emplace_back(pos[j], pos[i], A.values[p]);
    }
  const auto m = static_cast<Eigen::Index>(sorted.size());
  SpMat E(m, m);
  E.setFromTriplets(t.begin(), t.end());
  return E;
}

std::vector<int32_t> bfs_patch(const Adjacency& adj, int32_t seed, int32_t count) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1;
  std::vector<int32_t> order{seed};
  std::vector<uint8_t> seen(n, 0);
  seen[seed] = 1;
  for (size_t h = 0; h < order.size() && static_cast<int32_t>(order.size()) < count; ++h)
    for (int64_t p = adj.offsets[order[h]]; p < adj.offsets[order[h] + 1]; ++p) {
      const int32_t w = adj.neighbors[p];
      if (!seen[w] && static_cast<int32_t>(order.size()) < count) {
        seen[w] = 1;
        order.push_back(w);
      }
    }
  return order;
}

std::vector<int32_t> random_set(int32_t n, int32_t count, uint64_t seed) {
  std::vector<int32_t> all(n);
  std::iota(all.begin(), all.end(), 0);
  std::mt19937_64 rng(seed);
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(count);
  return all;  // unsorted on purpose
}

// Entries of a factor keyed by vertex pair (row vertex, column vertex), lower by factor order.
struct Entries {
  std::vector<std::pair<int64_t, double>> kv;  // key = rowvertex * n + colvertex
  double lookup(int64_t key) const {
    auto it = std::lower_bound(kv.begin(), kv.end(), std::make_pair(key, -HUGE_VAL));
    return it != kv.end() && it->first == key ? it->second : 0.0;
  }
};
Entries entries_by_vertex(const NumericFactor& F) {
  const SymbolicFactor& S = *F.symbolic;
  Entries e;
  for (int32_t s = 0; s < S.ns; ++s) {
    const int32_t f = S.super_first_col[s], k = S.ncols(s), m = S.nrows(s);
    const int32_t* rows = S.super_rows.data() + S.super_row_ptr[s];
    for (int32_t j = 0; j < k; ++j)
      for (int32_t t = j; t < m; ++t)
        e.kv.emplace_back(static_cast<int64_t>(S.perm[rows[t]]) * S.n + S.perm[f + j],
                          F.block(s)[static_cast<int64_t>(j) * m + t]);
  }
  std::sort(e.kv.begin(), e.kv.end());
  return e;
}

double max_factor_difference(const NumericFactor& A, const NumericFactor& B) {
  const Entries ea = entries_by_vertex(A), eb = entries_by_vertex(B);
  double diff = 0, scale = 0;
  for (const auto& [k, v] : ea.kv) { diff = std::max(diff, std::abs(v - eb.lookup(k))); scale = std::max(scale, std::abs(v)); }
  for (const auto& [k, v] : eb.kv) diff = std::max(diff, std::abs(v - ea.lookup(k)));
  return diff / scale;
}

struct Checked {
  FactorUpdate up;
  double residual = 0, vs_scratch = 0, vs_eigen = 0;
};

// Runs the update and checks it against the oracles; returns it for further checks.
Checked check_update(const NumericFactor& L, const CscMatrix& A, const std::vector<int32_t>& I, int threads = 0,
                     FactorUpdater* updater = nullptr, const FactorUpdateOptions& opt = {}) {
  RunContext ctx;
  ctx.threads = threads;
  Checked c;
  c.up = updater ? updater->update(I, ctx) : update_factor(L, A, I, ctx, opt);
  const FactorUpdate& up = c.up;
  std::vector<int32_t> sorted = I;
  std::sort(sorted.begin(), sorted.end());
  REQUIRE(up.vertices == sorted);
  const int32_t m = static_cast<int32_t>(sorted.size());
  REQUIRE(up.factor.n() == m);
  const SpMat E = submatrix_by_hand(A, sorted);
  CHECK((test::to_eigen(up.A_sub) - E).norm() == 0.0);

  // (i) residual of A_II x = b with the updated factor.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd b(m);
  for (int32_t i = 0; i < m; ++i) b[i] = u(rng);
  std::vector<double> x(b.data(), b.data() + m);
  solve(up.factor, x);
  const Eigen::Map<const Eigen::VectorXd> xv(x.data(), m);
  c.residual = (E * xv - b).norm() / b.norm();
  CHECK(c.residual <= 1e-10);
  Eigen::SimplicialLDLT<SpMat> ref(E);
  REQUIRE(ref.info() == Eigen::Success);
  const Eigen::VectorXd xe = ref.solve(b);
  c.vs_eigen = (xv - xe).norm() / xe.norm();
  CHECK(c.vs_eigen <= 1e-8);

  // (ii) the unique Cholesky factor in the same order, from scratch.
  auto S2 = analyze(up.A_sub, factor_ordering(*up.factor.symbolic));
  const NumericFactor F2 = factorize(S2, up.A_sub);
  c.vs_scratch = max_factor_difference(up.factor, F2);
  CHECK(c.vs_scratch <= 1e-10);
  // Stored structure holds the exact factor: never fewer entries than its exact count.
  CHECK(up.stats.nnz_stored >= S2->nnz_exact);
  return c;
}

struct Problem {
  Mesh mesh;
  CscMatrix A;
  NumericFactor L;
  Adjacency adj;
};

Problem make_problem(Mesh mesh, bool bilap) {
  Problem p;
  p.mesh = std::move(mesh);
  p.A = bilap ? bilaplacian(p.mesh, 1e-3) : regularized_laplacian(p.mesh);
  p.L = factorize(analyze(p.A, order_matrix(p.A)), p.A);
  p.adj = vertex_adjacency(p.mesh);
  return p;
}

// Two updates of the same set: the same A_II and the same symbolic factor. The
// assembly map (a_src, a_dst) is left to the callers: its order within a
// supernode's group may differ between the prepared and the one-shot path.
void check_same_structure(const FactorUpdate& a, const FactorUpdate& b) {
  const SymbolicFactor& Sa = *a.factor.symbolic;
  const SymbolicFactor& Sb = *b.factor.symbolic;
  CHECK(a.vertices == b.vertices);
  CHECK(a.A_sub.colptr == b.A_sub.colptr);
  CHECK(a.A_sub.rowind == b.A_sub.rowind);
  CHECK(a.A_sub.values == b.A_sub.values);
  CHECK(Sa.perm == Sb.perm);
  CHECK(Sa.parent == Sb.parent);
  CHECK(Sa.col_count == Sb.col_count);
  CHECK(Sa.nnz_exact == Sb.nnz_exact);
  CHECK(Sa.etree_height == Sb.etree_height);
  CHECK(Sa.super_etree_height == Sb.super_etree_height);
  CHECK(Sa.super_first_col == Sb.super_first_col);
  CHECK(Sa.super_parent == Sb.super_parent);
  CHECK(Sa.super_row_ptr == Sb.super_row_ptr);
  CHECK(Sa.super_rows == Sb.super_rows);
  CHECK(Sa.super_value_ptr == Sb.super_value_ptr);
  CHECK(Sa.nnz_L == Sb.nnz_L);
  CHECK(Sa.update_ptr == Sb.update_ptr);
  CHECK(Sa.update_from == Sb.update_from);
  CHECK(Sa.max_update_entries == Sb.max_update_entries);
  CHECK(Sa.max_super_rows == Sb.max_super_rows);
  CHECK(Sa.a_super_ptr == Sb.a_super_ptr);
  CHECK(Sa.a_nnz == Sb.a_nnz);
}

}  // namespace

TEST_CASE("update of BFS patches equals a from-scratch factorization (Laplacian and bi-Laplacian)") {
  struct MeshCase {
    const char* name;
    Mesh mesh;
  };
  std::vector<MeshCase> meshes;
  meshes.push_back({"icosphere", make_icosphere(4)});
  meshes.push_back({"random sphere", make_random_sphere(1500, 3)});
  meshes.push_back({"grid", make_grid(36, 0.2, 4)});
  for (auto& mc : meshes)
    for (bool bilap : {false, true}) {
      const Problem P = make_problem(mc.mesh, bilap);
      const int32_t n = P.A.ncols;
      std::mt19937_64 rng(11);
      double worst_fraction = 0;
      for (double frac : {0.1, 0.25, 0.5}) {
        const int32_t seed = static_cast<int32_t>(rng() % static_cast<uint64_t>(n));
        const std::vector<int32_t> I = bfs_patch(P.adj, seed, static_cast<int32_t>(frac * n));
        CAPTURE(mc.name);
        CAPTURE(bilap);
        CAPTURE(frac);
        const Checked c = check_update(P.L, P.A, I);
        worst_fraction = std::max(worst_fraction, c.up.stats.columns_updated_fraction);
        CHECK(c.up.stats.supernodes_recomputed <= c.up.stats.supernodes);
        CHECK(c.up.stats.columns_marked <= c.up.stats.columns_recomputed);
      }
      // The point of the method: a compact patch leaves part of the factor untouched.
      CHECK(worst_fraction < 1.0);
    }
}

TEST_CASE("scattered sets, a single vertex, two components and the whole set") {
  const Problem P = make_problem(make_icosphere(3), false);
  const int32_t n = P.A.ncols;
  int reordered = 0;
  for (int32_t count : {1, 2, 37, n / 3, n - 1}) {
    CAPTURE(count);
    reordered += check_update(P.L, P.A, random_set(n, count, 100 + count)).up.stats.reordered;
  }
  // Scattered sets split global subtrees: the postorder path must have run.
  CHECK(reordered > 0);
  SUBCASE("single vertex: L' = sqrt(a_vv)") {
    const FactorUpdate up = update_factor(P.L, P.A, std::vector<int32_t>{17});
    REQUIRE(up.factor.values.size() == 1);
    double a = 0;
    for (int64_t p = P.A.colptr[17]; p < P.A.colptr[18]; ++p)
      if (P.A.rowind[p] == 17) a = P.A.values[p];
    CHECK(std::abs(up.factor.values[0] - std::sqrt(a)) <= 1e-14 * std::sqrt(a));
  }
  SUBCASE("two separate patches") {
    std::vector<int32_t> I = bfs_patch(P.adj, 0, n / 8);
    const std::vector<int32_t> far = bfs_patch(P.adj, n - 1, n / 8);
    std::vector<uint8_t> in(n, 0);
    for (int32_t v : I) in[v] = 1;
    for (int32_t v : far)
      if (!in[v]) I.push_back(v);
    check_update(P.L, P.A, I);
  }
  SUBCASE("all vertices: a copy of L, nothing recomputed") {
    std::vector<int32_t> all = random_set(n, n, 3);
    const FactorUpdate up = update_factor(P.L, P.A, all);
    CHECK(up.stats.copied_whole);
    CHECK(up.stats.columns_recomputed == 0);
    CHECK(up.factor.symbolic == P.L.symbolic);
    CHECK(up.factor.values == P.L.values);
  }
}

TEST_CASE("a scattered set is factored afresh in L's relative order; the update path gives the same solves") {
  // Random vertices keep a small share of the columns of the supernodes they
  // touch (thesis Fig. 5.11): below refactor_below_share A_II is analysed and
  // factored from scratch. Oracles: check_update (residual, Eigen, a
  // from-scratch factor in the same order) and the forced update path.
  for (const bool bilap : {false, true}) {
    CAPTURE(bilap);
    const Problem P = make_problem(make_random_sphere(20000, 9), bilap);
    const int32_t n = P.A.ncols;
    const std::vector<int32_t> I = random_set(n, n / 10, 5);
    FactorUpdateOptions forced;
    forced.refactor_below_share = 0;
    const Checked fresh = check_update(P.L, P.A, I);  // one-shot path
    CHECK(fresh.up.stats.refactored);
    CHECK(fresh.up.stats.touched_share < FactorUpdateOptions{}.refactor_below_share);
    CHECK(fresh.up.stats.columns_recomputed == n / 10);
    FactorUpdater prepared(P.L, P.A), prepared_forced(P.L, P.A, forced);
    const Checked fresh2 = check_update(P.L, P.A, I, 2, &prepared);  // prepared path, 2 threads
    CHECK(fresh2.up.stats.refactored);
    CHECK(fresh2.up.factor.values == fresh.up.factor.values);
    const Checked upd = check_update(P.L, P.A, I, 1, &prepared_forced);
    CHECK_FALSE(upd.up.stats.refactored);
    CHECK(upd.up.stats.touched_share == fresh.up.stats.touched_share);
    // The update path stores the restricted structure of L: more than A_II's own factor.
    CHECK(upd.up.stats.nnz_stored > fresh.up.stats.nnz_stored);
    // The same perm (L's relative order), hence the same unique factor: equal solves.
    std::vector<double> x1(static_cast<size_t>(n / 10), 1.0), x2 = x1;
    solve(fresh.up.factor, x1);
    solve(upd.up.factor, x2);
    double diff = 0, norm = 0;
    for (size_t i = 0; i < x1.size(); ++i) {
      diff = std::max(diff, std::abs(x1[i] - x2[i]));
      norm = std::max(norm, std::abs(x2[i]));
    }
    CHECK(diff <= 1e-10 * norm);
    // A BFS patch keeps the update path; the refactored result cascades.
    CHECK_FALSE(check_update(P.L, P.A, bfs_patch(P.adj, 7, n / 10), 1, &prepared).up.stats.refactored);
    std::vector<int32_t> sub;
    for (int32_t a = 0; a < n / 10; a += 2) sub.push_back(a);
    check_update(fresh.up.factor, fresh.up.A_sub, sub);
    // A non-finite entry of A_II is named by its vertices, as on the update path.
    CscMatrix bad = P.A;
    const int32_t v = fresh.up.vertices[3];
    for (int64_t p = bad.colptr[v]; p < bad.colptr[v + 1]; ++p)
      if (bad.rowind[p] == v) bad.values[p] = std::nan("");
    FactorUpdater bad_up(P.L, bad);
    try {
      bad_up.update(I);
      FAIL("no error for a NaN entry");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::Numerical);
      CHECK(std::string(e.what()).find("vertices " + std::to_string(v) + " and " + std::to_string(v) + " is not finite") !=
            std::string::npos);
    }
  }
}

TEST_CASE("two mesh components: patches in one or both") {
  Mesh a = make_icosphere(3), b = make_icosphere(3, 2.0);
  const int32_t na = a.num_vertices();
  for (int32_t i = 0; i < b.num_vertices(); ++i) a.add_vertex(b.x[i] + 5, b.y[i], b.z[i]);
  for (int32_t f = 0; f < b.num_faces(); ++f) a.add_triangle(b.f0[f] + na, b.f1[f] + na, b.f2[f] + na);
  const Problem P = make_problem(std::move(a), false);
  const int32_t n = P.A.ncols;
  std::vector<int32_t> I = bfs_patch(P.adj, 3, na / 4);
  const std::vector<int32_t> other = bfs_patch(P.adj, na + 5, na / 3);
  check_update(P.L, P.A, I);
  I.insert(I.end(), other.begin(), other.end());
  check_update(P.L, P.A, I);
  // A whole component: no coupling to the rest, nothing to recompute.
  std::vector<int32_t> comp(na);
  std::iota(comp.begin(), comp.end(), 0);
  const Checked c = check_update(P.L, P.A, comp);
  CHECK(c.up.stats.columns_recomputed == 0);
  CHECK(n == 2 * na);
}

TEST_CASE("cascade: the updated factor is updated again for a subset") {
  const Problem P = make_problem(make_random_sphere(2000, 9), true);
  const std::vector<int32_t> I = bfs_patch(P.adj, 12, 1000);
  const Checked first = check_update(P.L, P.A, I);
  // Subset J of I, given in the local numbering of A_II: a smaller BFS patch.
  const std::vector<int32_t> inner = bfs_patch(P.adj, 12, 400);
  std::vector<int32_t> J;
  for (int32_t v : inner) {
    const auto it = std::lower_bound(first.up.vertices.begin(), first.up.vertices.end(), v);
    REQUIRE(it != first.up.vertices.end());
    J.push_back(static_cast<int32_t>(it - first.up.vertices.begin()));
  }
  const Checked second = check_update(first.up.factor, first.up.A_sub, J);
  // Same result as updating the global factor directly to `inner` (up to rounding).
  const FactorUpdate direct = update_factor(P.L, P.A, inner);
  CHECK(max_factor_difference(second.up.factor, direct.factor) <= 1e-10);
}

TEST_CASE("one FactorUpdater serves many vertex sets, also after refused ones") {
  for (const bool bilap : {false, true}) {
    CAPTURE(bilap);
    const Problem P = make_problem(make_icosphere(4), bilap);
    const int32_t n = P.A.ncols;
    FactorUpdater updater(P.L, P.A);
    std::mt19937 rng(5);
    for (int round = 0; round < 6; ++round) {
      CAPTURE(round);
      std::vector<int32_t> I;
      if (round % 3 == 2) {  // scattered
        for (int32_t v = 0; v < n; ++v)
          if (rng() % 7 == 0) I.push_back(v);
        std::shuffle(I.begin(), I.end(), rng);
      } else {
        I = bfs_patch(P.adj, static_cast<int32_t>(rng() % n), n / (round % 3 == 0 ? 10 : 2));
      }
      const Checked c = check_update(P.L, P.A, I, 2, &updater);
      CHECK(c.residual <= 1e-10);
      CHECK(c.vs_scratch <= 1e-10);
      // A refused set in between must leave the updater's maps clean.
      CHECK_THROWS_AS(updater.update(std::vector<int32_t>{I[0], 1, I[0]}), Error);
      CHECK_THROWS_AS(updater.update(std::vector<int32_t>{I[0], n}), Error);
    }
    const Checked single = check_update(P.L, P.A, {17}, 1, &updater);
    CHECK(single.residual <= 1e-10);
  }
}

TEST_CASE("the update is bit-identical for 1 and 2 threads") {
  const Problem P = make_problem(make_icosphere(4), false);
  const std::vector<int32_t> I = bfs_patch(P.adj, 100, P.A.ncols / 3);
  RunContext one, two;
  one.threads = 1;
  two.threads = 2;
  const FactorUpdate a = update_factor(P.L, P.A, I, one), b = update_factor(P.L, P.A, I, two);
  CHECK(a.factor.values == b.factor.values);
}

TEST_CASE("a prepared updater gives bit-identical results for 1 and 2 threads") {
  // With two threads the prepared updater splits its structure passes (the
  // touched supernodes in two halves, the update lists beside the column pass)
  // and extracts A_II beside the recomputation: every output must equal the
  // one-thread run's, for patches (restricted supernodes already in postorder
  // or not) and a scattered set, on a mesh large enough for parallel subtrees.
  // The two-thread updater also first-touches every result's pages beside the
  // structure (prefault_min_bytes = 0) and shares the copy of the unmarked
  // supernodes between its threads.
  for (const bool bilap : {false, true}) {
    CAPTURE(bilap);
    const Problem P = make_problem(make_random_sphere(20000, 9), bilap);
    const int32_t n = P.A.ncols;
    FactorUpdateOptions update_path, always_prefault;  // the scattered set too takes the update path
    update_path.refactor_below_share = always_prefault.refactor_below_share = 0;
    always_prefault.prefault_min_bytes = 0;
    FactorUpdater up1(P.L, P.A, update_path), up2(P.L, P.A, always_prefault);
    RunContext one, two;
    one.threads = 1;
    two.threads = 2;
    std::mt19937 rng(21);
    int reordered = 0, shared_copy = 0;
    for (int round = 0; round < 4; ++round) {
      CAPTURE(round);
      const std::vector<int32_t> I = round == 3 ? random_set(n, n / 4, 91)
                                                : bfs_patch(P.adj, static_cast<int32_t>(rng() % n), n / (2 + 3 * round));
      const FactorUpdate a = up1.update(I, one), b = up2.update(I, two);
      const SymbolicFactor& Sa = *a.factor.symbolic;
      const SymbolicFactor& Sb = *b.factor.symbolic;
      reordered += a.stats.reordered;
      shared_copy += b.stats.values_stored - b.stats.values_recomputed >= (int64_t{1} << 16);  // update_copy.cpp's bound
      CHECK(a.stats.reordered == b.stats.reordered);
      check_same_structure(a, b);
      CHECK(Sa.a_src == Sb.a_src);
      CHECK(Sa.a_dst == Sb.a_dst);
      CHECK(Sa.a_pattern_hash == Sb.a_pattern_hash);
      CHECK_NOTHROW(validate_symbolic(Sb, static_cast<int64_t>(b.factor.values.size())));
      CHECK(a.stats.columns_recomputed == b.stats.columns_recomputed);
      CHECK(a.factor.values == b.factor.values);
      // And the values are right (independent oracle): the two-thread result solves A_II.
      const int32_t m = static_cast<int32_t>(b.vertices.size());
      std::vector<double> rhs(static_cast<size_t>(m)), x;
      std::mt19937_64 r2(3);
      std::uniform_real_distribution<double> u(-1, 1);
      for (double& v : rhs) v = u(r2);
      x = rhs;
      solve(b.factor, x);
      const SpMat E = submatrix_by_hand(P.A, b.vertices);
      const Eigen::Map<const Eigen::VectorXd> xv(x.data(), m), bv(rhs.data(), m);
      CHECK((E * xv - bv).norm() / bv.norm() <= 1e-9);
    }
    CHECK(reordered > 0);    // the postorder path ran too
    CHECK(shared_copy > 0);  // and the shared copy
  }
}

TEST_CASE("bad vertex sets and mismatched matrices are usage errors") {
  const Problem P = make_problem(make_icosphere(2), false);
  const int32_t n = P.A.ncols;
  auto code_of = [&](const std::vector<int32_t>& I, const CscMatrix& A) {
    try {
      update_factor(P.L, A, I);
    } catch (const Error& e) {
      return e.code();
    }
    return ErrorCode::Internal;
  };
  CHECK(code_of({}, P.A) == ErrorCode::BadUsage);
  CHECK(code_of({0, 5, 5}, P.A) == ErrorCode::BadUsage);
  CHECK(code_of({-1}, P.A) == ErrorCode::BadUsage);
  CHECK(code_of({n}, P.A) == ErrorCode::BadUsage);
  const CscMatrix other = regularized_laplacian(make_icosphere(1));
  CHECK(code_of({0, 1}, other) == ErrorCode::BadUsage);
  try {
    update_factor(P.L, P.A, std::vector<int32_t>{3, 9, 3});
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("vertex 3 appears twice") != std::string::npos);
  }
}

TEST_CASE("a non-positive pivot of A_II names the global vertex") {
  // A principal submatrix of an SPD matrix is SPD, so with consistent inputs
  // this cannot fail (and the singular -L_C of a closed mesh is not reliably
  // rejected even by a full factorization: rounding leaves a tiny positive last
  // pivot). To reach the error path, A's values at one vertex of I are changed after
  // L was computed (same pattern): its diagonal becomes negative. The vertex
  // chosen has a neighbor in B eliminated before it, so row v of L has an
  // entry in a column of B and column v is always recomputed. The message must
  // carry the global id, not the local one.
  const Problem P = make_problem(make_icosphere(3), false);
  const int32_t n = P.A.ncols;
  std::vector<int32_t> I = bfs_patch(P.adj, 40, n / 4);
  std::vector<uint8_t> in(n, 0);
  for (int32_t v : I) in[v] = 1;
  const auto& ip = P.L.symbolic->iperm;
  int32_t root = -1;
  for (int32_t v : I)
    for (int64_t p = P.adj.offsets[v]; p < P.adj.offsets[v + 1]; ++p)
      if (!in[P.adj.neighbors[p]] && ip[P.adj.neighbors[p]] < ip[v] && root < 0) root = v;
  REQUIRE(root >= 0);
  CscMatrix bad = P.A;
  for (int64_t p = bad.colptr[root]; p < bad.colptr[root + 1]; ++p)
    if (bad.rowind[p] == root) bad.values[p] = -1.0;
  try {
    update_factor(P.L, bad, I);
    FAIL("expected Error(Numerical)");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::Numerical);
    CHECK(std::string(e.what()).find("vertex " + std::to_string(root) + " ") != std::string::npos);
  }
  // With caller ids (a cascade names the mesh vertices), the id is used instead.
  std::vector<int32_t> ids(n);
  for (int32_t i = 0; i < n; ++i) ids[i] = 100000 + i;
  FactorUpdateOptions opt;
  opt.vertex_ids = ids;
  try {
    update_factor(P.L, bad, I, {}, opt);
    FAIL("expected Error(Numerical)");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("vertex " + std::to_string(100000 + root) + " ") != std::string::npos);
  }
}

TEST_CASE("a prepared updater builds the same submesh factor as the one-shot path and complete_symbolic") {
  // The prepared FactorUpdater reads A_II from its copy of A in factor order and
  // derives the symbolic parts itself; the one-shot path gathers A_II from A and
  // calls complete_symbolic. Both must give the same matrix, the same symbolic
  // factor and the same values bit for bit (same arithmetic).
  for (const bool bilap : {false, true}) {
    CAPTURE(bilap);
    const Problem P = make_problem(make_random_sphere(3000, 4), bilap);
    const int32_t n = P.A.ncols;
    FactorUpdater prepared(P.L, P.A);
    std::mt19937 rng(8);
    for (int round = 0; round < 4; ++round) {
      CAPTURE(round);
      const std::vector<int32_t> I = round == 3 ? random_set(n, n / 5, 77)
                                                : bfs_patch(P.adj, static_cast<int32_t>(rng() % n), n / (2 + 2 * round));
      const FactorUpdate a = prepared.update(I), b = update_factor(P.L, P.A, I);
      const SymbolicFactor& Sa = *a.factor.symbolic;
      const SymbolicFactor& Sb = *b.factor.symbolic;
      check_same_structure(a, b);
      CHECK(Sa.a_pattern_hash == pattern_hash(a.A_sub));
      // Same assembly: every L position receives the same A_II entry (the order
      // within a supernode's group may differ).
      std::vector<std::pair<int64_t, int64_t>> ma, mb;
      for (size_t q = 0; q < Sa.a_src.size(); ++q) ma.emplace_back(Sa.a_dst[q], Sa.a_src[q]);
      for (size_t q = 0; q < Sb.a_src.size(); ++q) mb.emplace_back(Sb.a_dst[q], Sb.a_src[q]);
      std::sort(ma.begin(), ma.end());
      std::sort(mb.begin(), mb.end());
      CHECK(ma == mb);
      CHECK_NOTHROW(validate_symbolic(Sa, static_cast<int64_t>(a.factor.values.size())));
      CHECK(a.factor.values == b.factor.values);
    }
  }
}

TEST_CASE("a non-finite entry of A_II is refused naming its vertices") {
  const Problem P = make_problem(make_icosphere(3), false);
  CscMatrix bad = P.A;
  const int32_t v = 30;
  bad.values[static_cast<size_t>(bad.colptr[v])] = std::nan("");  // first stored entry of column v (its diagonal or below)
  const int32_t row = bad.rowind[static_cast<size_t>(bad.colptr[v])];
  const std::vector<int32_t> I = bfs_patch(P.adj, v, P.A.ncols / 3);
  REQUIRE(std::find(I.begin(), I.end(), row) != I.end());
  for (const bool prepared : {true, false}) {
    CAPTURE(prepared);
    try {
      FactorUpdater(P.L, bad, {}, prepared).update(I);
      FAIL("expected Error(Numerical)");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::Numerical);
      CHECK(std::string(e.what()).find("not finite") != std::string::npos);
      if (prepared) CHECK(std::string(e.what()).find("vertices " + std::to_string(std::max(v, row))) != std::string::npos);
    }
  }
}

TEST_CASE("a non-finite entry in a recomputed supernode keeps its message (prepared updater, 1 and 2 threads)") {
  // The prepared updater assembles the recomputed supernodes straight from A,
  // inside the factorization, beside A_II's extraction: a NaN there surfaces
  // from the factorization but is not a pivot failure. It must reach the caller
  // unchanged, naming both vertices, as a plain Error, whichever thread count;
  // and the updater's maps must be left clean for the next set. The vertex
  // has a neighbor in B eliminated before it, so its column is recomputed.
  const Problem P = make_problem(make_icosphere(3), false);
  const int32_t n = P.A.ncols;
  const std::vector<int32_t> I = bfs_patch(P.adj, 40, n / 4);
  std::vector<uint8_t> in(n, 0);
  for (int32_t v : I) in[v] = 1;
  const auto& ip = P.L.symbolic->iperm;
  int32_t root = -1;
  for (int32_t v : I)
    for (int64_t p = P.adj.offsets[v]; p < P.adj.offsets[v + 1]; ++p)
      if (!in[P.adj.neighbors[p]] && ip[P.adj.neighbors[p]] < ip[v] && root < 0) root = v;
  REQUIRE(root >= 0);
  CscMatrix bad = P.A;
  for (int64_t p = bad.colptr[root]; p < bad.colptr[root + 1]; ++p)
    if (bad.rowind[p] == root) bad.values[p] = std::nan("");
  const std::string expected =
      "submatrix entry of vertices " + std::to_string(root) + " and " + std::to_string(root) + " is not finite";
  for (const int threads : {1, 2}) {
    CAPTURE(threads);
    RunContext ctx;
    ctx.threads = threads;
    FactorUpdater up(P.L, bad);
    for (int round = 0; round < 2; ++round) {  // the second round finds the maps reset
      try {
        up.update(I, ctx);
        FAIL("expected Error(Numerical)");
      } catch (const Error& e) {
        CHECK(typeid(e) == typeid(Error));
        CHECK(e.code() == ErrorCode::Numerical);
        CHECK(std::string(e.what()) == expected);
      }
    }
    // A set without the vertex is still updated by the same updater.
    std::vector<int32_t> rest;
    for (int32_t v : I)
      if (v != root) rest.push_back(v);
    const FactorUpdate ok = up.update(rest, ctx);
    CHECK_FALSE(ok.stats.refactored);
    CHECK(ok.stats.n_sub == static_cast<int32_t>(rest.size()));
  }
}

TEST_CASE("the sharing updater borrows L's unchanged blocks: same values, L kept alive, cascades, refactorize") {
  // The sharing form (L by shared pointer) must give, block for block, the
  // copying form's values (bit for bit, 1 and 2 threads), store only the
  // blocks it does not borrow, and keep L's storage alive on its own; without
  // A_II (submatrix = false) the factor is the same. Oracles: the copying
  // form (itself checked above against a from-scratch factorization) and the
  // residual of A_II x = b with A_II assembled by hand.
  for (const bool bilap : {false, true}) {
    CAPTURE(bilap);
    const Problem P = make_problem(make_random_sphere(20000, 9), bilap);
    const int32_t n = P.A.ncols;
    auto Lp = std::make_shared<const NumericFactor>(P.L);
    FactorUpdateOptions update_path, factor_only;  // the scattered set too takes the update path
    update_path.refactor_below_share = factor_only.refactor_below_share = 0;
    factor_only.submatrix = false;
    FactorUpdater copying(P.L, P.A, update_path), sharing(Lp, P.A, update_path), sharing_fo(Lp, P.A, factor_only);
    auto residual = [&](const FactorUpdate& u) {
      const int32_t m = static_cast<int32_t>(u.vertices.size());
      std::vector<double> rhs(static_cast<size_t>(m));
      std::mt19937_64 r2(3);
      std::uniform_real_distribution<double> d(-1, 1);
      for (double& v : rhs) v = d(r2);
      std::vector<double> x = rhs;
      solve(u.factor, x);
      const SpMat E = submatrix_by_hand(P.A, u.vertices);
      const Eigen::Map<const Eigen::VectorXd> xv(x.data(), m), bv(rhs.data(), m);
      return (E * xv - bv).norm() / bv.norm();
    };
    int64_t borrowed_total = 0;
    for (const int threads : {1, 2}) {
      RunContext ctx;
      ctx.threads = threads;
      std::mt19937 rng(33);
      for (int round = 0; round < 4; ++round) {
        CAPTURE(threads);
        CAPTURE(round);
        const std::vector<int32_t> I = round == 3 ? random_set(n, n / 4, 17)
                                                  : bfs_patch(P.adj, static_cast<int32_t>(rng() % n), n / (2 + 3 * round));
        const FactorUpdate a = copying.update(I, ctx), b = sharing.update(I, ctx), c = sharing_fo.update(I, ctx);
        check_same_structure(a, b);
        const SymbolicFactor& S = *a.factor.symbolic;
        REQUIRE(b.factor.borrows());
        REQUIRE(c.factor.borrows());
        CHECK(c.A_sub.ncols == 0);  // not extracted
        CHECK(c.factor.symbolic->super_rows == S.super_rows);
        CHECK(c.factor.symbolic->super_value_ptr == S.super_value_ptr);
        CHECK(b.stats.values_borrowed == c.stats.values_borrowed);
        CHECK(static_cast<int64_t>(b.factor.values.size()) + b.stats.values_borrowed == b.stats.values_stored);
        borrowed_total += b.stats.values_borrowed;
        bool same_b = true, same_c = true;
        for (int32_t s = 0; s < S.ns; ++s) {
          const int64_t size = S.super_value_ptr[s + 1] - S.super_value_ptr[s];
          same_b = same_b && std::equal(a.factor.block(s), a.factor.block(s) + size, b.factor.block(s));
          same_c = same_c && std::equal(a.factor.block(s), a.factor.block(s) + size, c.factor.block(s));
        }
        CHECK(same_b);
        CHECK(same_c);
        CHECK(residual(c) <= 1e-9);
      }
    }
    CHECK(borrowed_total > 0);

    // Lifetime: the result outlives its updater and every other owner of L.
    const std::vector<int32_t> I = bfs_patch(P.adj, 7, n / 3);
    FactorUpdate kept;
    {
      auto L2 = std::make_shared<const NumericFactor>(P.L);
      FactorUpdater u(L2, P.A);
      kept = u.update(I);
    }
    REQUIRE(kept.factor.borrows());
    CHECK(residual(kept) <= 1e-9);

    // Cascade from a borrowing factor (its blocks then come from two lenders),
    // which again outlives everything else.
    const std::vector<int32_t> inner = bfs_patch(P.adj, 7, n / 8);
    std::vector<int32_t> J;
    for (int32_t v : inner)
      J.push_back(static_cast<int32_t>(std::lower_bound(kept.vertices.begin(), kept.vertices.end(), v) - kept.vertices.begin()));
    FactorUpdate second;
    {
      auto first = std::make_shared<const NumericFactor>(kept.factor);
      FactorUpdater u(first, kept.A_sub);
      second = u.update(J);
    }
    const FactorUpdate direct = update_factor(P.L, P.A, inner);
    CHECK(max_factor_difference(second.factor, direct.factor) <= 1e-10);
    {
      // (second's vertices are local to kept's numbering: residual against A_II of `inner`)
      // (the bi-Laplacian's A_II is ill-conditioned: measured against the direct update's residual)
      const int32_t m = static_cast<int32_t>(J.size());
      std::vector<double> rhs(static_cast<size_t>(m), 1.0), x = rhs, xd = rhs;
      solve(second.factor, x);
      solve(direct.factor, xd);
      const SpMat E = submatrix_by_hand(P.A, direct.vertices);
      const Eigen::Map<const Eigen::VectorXd> xv(x.data(), m), xdv(xd.data(), m), bv(rhs.data(), m);
      const double res = (E * xv - bv).norm() / bv.norm(), res_direct = (E * xdv - bv).norm() / bv.norm();
      CHECK(res <= std::max(1e-9, 10 * res_direct));
    }

    // A borrowed block cannot be recomputed in place; refactorize owns every block again.
    NumericFactor r = kept.factor;
    int32_t borrowed_s = -1;
    for (int32_t s = 0; s < r.symbolic->ns && borrowed_s < 0; ++s)
      if (r.borrowed[s]) borrowed_s = s;
    REQUIRE(borrowed_s >= 0);
    std::vector<uint8_t> mask(static_cast<size_t>(r.symbolic->ns), 0);
    mask[borrowed_s] = 1;
    CHECK_THROWS_AS(factorize_supernodes(r, kept.A_sub, mask), Error);
    refactorize(r, kept.A_sub);
    CHECK_FALSE(r.borrows());
    CHECK(static_cast<int64_t>(r.values.size()) == r.symbolic->super_value_ptr[r.symbolic->ns]);
    CHECK(max_factor_difference(r, kept.factor) <= 1e-10);
  }
}
