// Tests for io/factor_cache: round trip (bit-identical solves), refusal of
// other meshes and format versions, truncated and corrupted files, and the
// structural validator on inconsistent factors.
#include "locus/io/factor_cache.hpp"

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "../kernels/matrix_fixtures.hpp"

using namespace locus;

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("locus_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::vector<char> slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& p, const std::vector<char>& d) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(d.data(), static_cast<std::streamsize>(d.size()));
}

}  // namespace

TEST_CASE("factor cache round trip gives bit-identical solves") {
  const CscMatrix A = test::grid_laplacian(60, 50, 0.01);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const std::string path = temp_path("rt.locus");
  save_factor(path, F, {12345, "heat", 0.5});
  FactorCacheInfo info;
  const NumericFactor G = load_factor(path, info, 12345);
  CHECK(info.mesh_hash == 12345);
  CHECK(info.operator_kind == "heat");
  CHECK(info.t == 0.5);
  CHECK(G.symbolic->perm == F.symbolic->perm);
  CHECK(G.symbolic->update_from == F.symbolic->update_from);
  CHECK(G.symbolic->max_update_entries == F.symbolic->max_update_entries);
  std::vector<double> b(A.ncols, 1.0), c = b;
  solve(F, b);
  solve(G, c);
  CHECK(b == c);
  // The loaded factor refactorizes too (assembly map survived).
  NumericFactor H = G;
  CHECK_NOTHROW(refactorize(H, A));
  CHECK(std::equal(H.values.begin(), H.values.end(), F.values.begin()));
  CHECK_THROWS_AS(load_factor(path, info, 999), Error);  // another mesh
  std::remove(path.c_str());
}

TEST_CASE("factor cache refuses other versions, truncated and corrupted files") {
  const CscMatrix A = test::grid_laplacian(20, 20, 0.1);
  const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
  const std::string path = temp_path("bad.locus"), broken = temp_path("broken.locus");
  save_factor(path, F, {7, "laplacian", 0});
  const std::vector<char> good = slurp(path);
  FactorCacheInfo info;
  auto expect_bad = [&](const std::vector<char>& data, const char* what) {
    spit(broken, data);
    CAPTURE(what);
    try {
      load_factor(broken, info);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::BadInput);
      CHECK(std::string(e.what()).find(broken) != std::string::npos);
    }
  };
  std::vector<char> v = good;
  v[8] = 2;  // format version
  expect_bad(v, "version");
  expect_bad({}, "empty");
  for (size_t cut : {size_t(10), size_t(30), good.size() / 3, good.size() / 2, good.size() - 1}) expect_bad({good.begin(), good.begin() + cut}, "truncated");
  v = good;
  v[0] = 'X';
  expect_bad(v, "magic");
  // Flipped bytes anywhere: refused, or (only in padding) loaded with identical results.
  std::mt19937_64 rng(1);
  std::vector<double> ref(A.ncols, 1.0);
  solve(F, ref);
  for (int trial = 0; trial < 60; ++trial) {
    v = good;
    const size_t at = std::uniform_int_distribution<size_t>(0, v.size() - 1)(rng);
    v[at] = static_cast<char>(v[at] ^ (1 + trial % 255));
    spit(broken, v);
    try {
      const NumericFactor G = load_factor(broken, info);
      std::vector<double> x(A.ncols, 1.0);
      solve(G, x);
      CHECK(x == ref);
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::BadInput);
    }
  }
  CHECK_THROWS_AS(load_factor(temp_path("missing.locus"), info), Error);
  CHECK_THROWS_AS(load_factor(std::filesystem::temp_directory_path().string(), info), Error);
  std::remove(path.c_str());
  std::remove(broken.c_str());
}

TEST_CASE("validate_symbolic catches inconsistent structures") {
  const CscMatrix A = test::grid_laplacian(15, 12, 0.1);
  auto S = analyze(A, order_matrix(A));
  CHECK_NOTHROW(validate_symbolic(*S, S->super_value_ptr[S->ns]));
  auto broken = [&](auto mutate) {
    SymbolicFactor T = *S;
    mutate(T);
    CHECK_THROWS_AS(validate_symbolic(T, -1), Error);
  };
  broken([](SymbolicFactor& T) { T.perm[0] = T.perm[1]; });
  broken([](SymbolicFactor& T) { T.super_rows.back() = T.n; });
  broken([](SymbolicFactor& T) { T.super_parent[0] = 0; });
  broken([](SymbolicFactor& T) { T.super_value_ptr[1] += 1; });
  broken([](SymbolicFactor& T) { T.a_dst[0] = -1; });
}

TEST_CASE("factor cache refuses a factor that borrows blocks from another factor") {
  const CscMatrix A = test::grid_laplacian(40, 40, 0.01);
  auto F = std::make_shared<const NumericFactor>(factorize(analyze(A, order_matrix(A)), A));
  std::vector<int32_t> I;
  for (int32_t v = 0; v < A.ncols / 2; ++v) I.push_back(v);  // half the grid: many blocks kept whole
  FactorUpdater up(F, A);
  const FactorUpdate U = up.update(I);
  REQUIRE(U.factor.borrows());
  REQUIRE(U.stats.values_borrowed > 0);
  const std::string path = temp_path("borrow.locus");
  try {
    save_factor(path, U.factor, {1, "heat", 0.5});
    FAIL("a borrowing factor was saved");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadUsage);
    CHECK(std::string(e.what()).find("borrows") != std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(path));
  // Once it owns its blocks again (refactorize), it is cached like any other.
  NumericFactor G = U.factor;
  refactorize(G, U.A_sub);
  CHECK_NOTHROW(save_factor(path, G, {1, "heat", 0.5}));
  std::remove(path.c_str());
}
