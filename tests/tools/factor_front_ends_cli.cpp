// One orchestration: `locus factor`, locus::Session::factor and the C API
// (locus_factor_run) give bit-identical factors' sizes and residuals on
// armadillo, and the Session and the C API the same solution bit for bit
// (Python: tests/python/test_front_ends.py). The CLI's doubles are read back
// from its JSON (printed to round-trip). The solution itself is checked
// against an independent solver (Eigen's simplicial LDL^T of the same matrix).
#include <doctest/doctest.h>

#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "locus/engine/factor_request.hpp"
#include "locus/kernels/solve/solve_accuracy.hpp"
#include "locus/locus.h"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tests/kernels/matrix_fixtures.hpp"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

const std::string kArmadillo = LOCUS_MESH_CACHE_DIR "/armadillo.off";

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

// A x = b by Eigen's simplicial LDL^T of the symmetric matrix whose lower triangle A stores.
std::vector<double> eigen_solve(const locus::CscMatrix& A, const std::vector<double>& b) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(locus::test::to_eigen(A));
  REQUIRE(ldlt.info() == Eigen::Success);
  const Eigen::VectorXd x = ldlt.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), static_cast<Eigen::Index>(b.size())));
  return {x.data(), x.data() + x.size()};
}

}  // namespace

TEST_CASE("factor: the CLI, the Session and the C API agree bit for bit") {
  if (!have_locus() || !std::filesystem::exists(kArmadillo)) return;
  Scratch dir("front-ends-factor");
  const locus::Session s = locus::Session::from_file(kArmadillo);
  locus_session* c = nullptr;
  REQUIRE(locus_session_create_from_file(kArmadillo.c_str(), &c) == LOCUS_OK);
  struct Case {
    std::vector<std::string> args;
    locus::FactorCommandRequest q;
  };
  locus::FactorCommandRequest heat;
  heat.t = "2h2";
  heat.seed = 3;
  heat.repeat = 2;
  locus::FactorCommandRequest laplacian;
  laplacian.matrix = "laplacian";
  // --operator is the older spelling of --matrix: the same request.
  for (const Case& k : {Case{{"--t", "2h2", "--seed", "3", "--repeat", "2"}, heat},
                        Case{{"--matrix", "laplacian"}, laplacian}, Case{{"--operator", "laplacian"}, laplacian}}) {
    CAPTURE(k.args.front());
    std::vector<std::string> args = {"factor", kArmadillo, "--threads", "2", "--json"};
    args.insert(args.end(), k.args.begin(), k.args.end());
    const Run run = run_locus(dir, args);
    REQUIRE_MESSAGE(run.status == 0, run.err);
    const nlohmann::json j = nlohmann::json::parse(run.out);

    const locus::FactorCommandReport r = s.factor(k.q);
    CHECK(j["operator"] == r.matrix);
    CHECK(j["n"] == r.n);
    CHECK(j["repeats"] == r.repeats);
    CHECK(j["nnz_A"] == r.nnz_A);
    CHECK(j["nnz_L"] == r.nnz_L);
    CHECK(j["nnz_L_exact"] == r.nnz_L_exact);
    CHECK(j["supernodes"] == r.supernodes);
    CHECK(j["etree_height"] == r.etree_height);
    CHECK(j["flops"] == r.flops);
    CHECK(j["t"].get<double>() == r.t);
    CHECK(j["h"].get<double>() == r.h);
    CHECK(j["residual"].get<double>() == r.residual);
    CHECK(j["residual8"].get<double>() == r.residual8);
    CHECK(j["solve8_lane0_vs_solve"].get<double>() == r.lane0_vs_solve);

    locus_factor_options o = locus_factor_options_default();
    if (k.q.matrix != "heat") o.matrix = k.q.matrix.c_str();
    if (!k.q.t.empty()) o.t = k.q.t.c_str();
    o.seed = k.q.seed, o.repeat = k.q.repeat;
    std::vector<double> x(static_cast<size_t>(s.num_vertices()));
    locus_factor_report rep;
    REQUIRE(locus_factor_run(c, &o, x.data(), &rep, nullptr) == LOCUS_OK);
    CHECK(same_bits(x, r.x));
    CHECK(rep.n == r.n);
    CHECK(rep.repeats == r.repeats);
    CHECK(rep.nnz_L == r.nnz_L);
    CHECK(rep.flops == r.flops);
    CHECK(rep.t == r.t);
    CHECK(rep.residual == r.residual);
    CHECK(rep.residual8 == r.residual8);
    CHECK(rep.lane0_vs_solve == r.lane0_vs_solve);
  }
  // The oracle: the heat matrix's solution by another solver, and its residual recomputed.
  const locus::FactorCommandReport r = s.factor(heat);
  const locus::FactorMatrix A = locus::factor_matrix(s.mesh(), heat);
  CHECK(A.t == r.t);
  const std::vector<double> b = locus::random_vector(static_cast<size_t>(A.A.ncols), heat.seed);
  const std::vector<double> want = eigen_solve(A.A, b);
  double err = 0, norm = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    err = std::max(err, std::abs(r.x[i] - want[i]));
    norm = std::max(norm, std::abs(want[i]));
  }
  CHECK(err <= 1e-10 * norm);
  CHECK(r.residual == locus::relative_residual(A.A, r.x.data(), b.data()));
  CHECK(r.residual < 1e-12);
  // Refusals: the engine's checks, one status everywhere.
  locus_factor_options bad = locus_factor_options_default();
  bad.matrix = "cholesky";
  CHECK(locus_factor_run(c, &bad, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad = locus_factor_options_default();
  bad.matrix = "laplacian";
  bad.t = "2h2";  // t is the heat matrix's
  CHECK(locus_factor_run(c, &bad, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad = locus_factor_options_default();
  bad.repeat = 0;
  CHECK(locus_factor_run(c, &bad, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  bad = locus_factor_options_default();
  bad.save = "f.locus";
  bad.load = "g.locus";
  CHECK(locus_factor_run(c, &bad, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(run_locus(dir, {"factor", kArmadillo, "--matrix", "heat", "--operator", "laplacian"}).status == 2);
  CHECK(run_locus(dir, {"factor", kArmadillo, "--matrix", "laplacian", "--t", "2h2"}).status == 2);
  locus_session_destroy(c);
}
