// Tests for kernels/src/mesh/robust_laplacian.cpp (with tufted_cover.cpp,
// intrinsic_mollification.cpp, intrinsic_delaunay.cpp).
// Oracles: the cotan operator of mesh_operators.cpp on meshes whose triangulation
// is already Delaunay (the tufted cover's two sheets halve back to it); on planar
// meshes, linear precision (L x = 0 at interior vertices, for any planar
// triangulation), the polygon's area, and Rippa's theorem (the Delaunay
// triangulation has the least Dirichlet energy of all triangulations of the same
// points, so u^T (-L) u can only go down); Eigen's dense LLT for definiteness; the
// M-matrix property (M - tL with non-positive off-diagonals is inverse-positive on
// a connected mesh) for the heat-like solve.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "locus/kernels/mesh/mesh_defects.hpp"
#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/kernels/mesh/tufted_cover.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"

using namespace locus;

namespace {

Eigen::MatrixXd dense(const CscMatrix& A) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(A.nrows, A.ncols);
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      D(A.rowind[p], j) = A.values[p];
      D(j, A.rowind[p]) = A.values[p];
    }
  return D;
}

// Lower storage as the factorization expects it: rows ascending, diagonal first,
// every row index in range and >= its column.
void check_lower_csc(const CscMatrix& A, int32_t n) {
  REQUIRE(A.nrows == n);
  REQUIRE(A.ncols == n);
  REQUIRE(A.colptr.size() == static_cast<size_t>(n) + 1);
  for (int32_t j = 0; j < n; ++j) {
    REQUIRE(A.colptr[j + 1] > A.colptr[j]);
    REQUIRE(A.rowind[A.colptr[j]] == j);
    for (int64_t p = A.colptr[j] + 1; p < A.colptr[j + 1]; ++p) {
      REQUIRE(A.rowind[p] > A.rowind[p - 1]);
      REQUIRE(A.rowind[p] < n);
    }
  }
}

struct Signs {
  double min_offdiag = 0.0, max_row_sum = 0.0, max_weight = 0.0;
};

Signs signs(const CscMatrix& L) {
  const Eigen::MatrixXd D = dense(L);
  Signs s;
  for (int i = 0; i < D.rows(); ++i) {
    s.max_row_sum = std::max(s.max_row_sum, std::abs(D.row(i).sum()));
    for (int j = 0; j < D.cols(); ++j)
      if (i != j) {
        s.min_offdiag = std::min(s.min_offdiag, D(i, j));
        s.max_weight = std::max(s.max_weight, D(i, j));
      }
  }
  return s;
}

void compare_with_cotan(const Mesh& m, double mollify, double tol) {
  RobustLaplacianOptions opt;
  opt.mollify_relative = mollify;
  const RobustOperators R = robust_laplacian(m, opt);
  const Eigen::MatrixXd Lr = dense(R.L), Lc = dense(cotan_laplacian(m));
  const HostVector<double> mc = lumped_mass(m);
  const double scale = Lc.cwiseAbs().maxCoeff();
  CHECK((Lr - Lc).cwiseAbs().maxCoeff() <= tol * scale);
  double mass_scale = 0.0, mass_err = 0.0;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    mass_scale = std::max(mass_scale, mc[v]);
    mass_err = std::max(mass_err, std::abs(R.mass[v] - mc[v]));
  }
  CHECK(mass_err <= tol * mass_scale);
  CHECK(R.flips.flips == 0);
  CHECK(R.isolated_vertices == 0);
}

}  // namespace

TEST_CASE("robust Laplacian: the tufted cover of a closed manifold mesh is two sheets") {
  const Mesh m = make_icosphere(2);
  const IntrinsicTriangulation T = tufted_cover(m);
  REQUIRE(T.num_faces() == 2 * m.num_faces());
  for (int32_t s = 0; s < static_cast<int32_t>(T.twin.size()); ++s) {
    REQUIRE(T.twin[s] >= 0);
    CHECK(T.twin[T.twin[s]] == s);
    CHECK(T.vertex[T.twin[s]] == T.vertex[side_next(s)]);  // glued sides run opposite ways
    CHECK(T.length[T.twin[s]] == T.length[s]);
    CHECK(T.twin[s] / 3 % 2 == s / 3 % 2);  // front faces glue to front faces
  }
}

TEST_CASE("robust Laplacian: equals the cotan operator on Delaunay meshes") {
  // Without mollification the only difference is rounding in the length-based
  // cotangents (Heron vs cross products): well below 1e-12 of the largest entry.
  compare_with_cotan(make_icosphere(3), 0.0, 1e-12);
  compare_with_cotan(make_grid(8), 0.0, 1e-12);
  // With the default mollification: every margin a + b - c of these meshes is
  // above 1e-5 h, so epsilon is 0 and nothing changes.
  const RobustOperators R = robust_laplacian(make_icosphere(3));
  CHECK(R.mollify_epsilon == 0.0);
  compare_with_cotan(make_icosphere(3), kMollifyRelative, 1e-12);
}

TEST_CASE("robust Laplacian: a non-Delaunay planar mesh gets non-negative weights and keeps linear precision") {
  const Mesh m = make_disk(6, 0.6, 7);
  const int32_t n = m.num_vertices();
  const Signs sc = signs(cotan_laplacian(m));
  REQUIRE(sc.min_offdiag < -1e-3);  // the flips made the cotan operator non-Delaunay
  const RobustOperators R = robust_laplacian(m);
  check_lower_csc(R.L, n);
  check_lower_csc(R.M, n);
  CHECK(R.flips.converged);
  CHECK(R.flips.flips > 0);
  const Signs sr = signs(R.L);
  CHECK(sr.min_offdiag >= 0.0);
  CHECK(sr.max_row_sum <= 1e-12 * sr.max_weight);
  // Linear precision at interior vertices (the boundary is the last ring: 6 * 6).
  const Eigen::MatrixXd L = dense(R.L);
  Eigen::VectorXd x(n), y(n);
  for (int32_t v = 0; v < n; ++v) x[v] = m.x[v], y[v] = m.y[v];
  const Eigen::VectorXd lx = L * x, ly = L * y;
  for (int32_t v = 0; v < n - 36; ++v) {
    CHECK(std::abs(lx[v]) <= 1e-12 * sr.max_weight);
    CHECK(std::abs(ly[v]) <= 1e-12 * sr.max_weight);
  }
  // Mass: the area of the 36-gon inscribed in the unit circle.
  double area = 0.0;
  for (double a : R.mass) area += a;
  CHECK(area == doctest::Approx(0.5 * 36 * std::sin(2 * M_PI / 36)).epsilon(1e-12));
  // Rippa: the Delaunay energy is never above the given triangulation's.
  const Eigen::MatrixXd Lc = dense(cotan_laplacian(m));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd u(n);
    for (int32_t v = 0; v < n; ++v) u[v] = U(rng);
    const double er = -u.dot(L * u), ec = -u.dot(Lc * u);
    CHECK(er <= ec * (1 + 1e-12));
    CHECK(er > 0.0);
  }
}

TEST_CASE("robust Laplacian: planted defects give a symmetric, definite heat operator with a positive solution") {
  const Mesh clean = make_icosphere(2);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const PlantedDefect kind = static_cast<PlantedDefect>(k);
    const Mesh m = plant_mesh_defect(clean, kind, 4);
    CAPTURE(planted_defect_name(kind));
    const int32_t n = m.num_vertices();
    const RobustOperators R = robust_laplacian(m);
    check_lower_csc(R.L, n);
    CHECK(R.flips.converged);
    const Signs s = signs(R.L);
    CHECK(s.min_offdiag >= 0.0);
    CHECK(s.max_row_sum <= 1e-12 * s.max_weight);
    const double h = mean_edge_length(m);
    const Eigen::MatrixXd A = dense(R.M) - h * h * dense(R.L);
    const Eigen::LLT<Eigen::MatrixXd> llt(A);
    REQUIRE(llt.info() == Eigen::Success);
    // Heat from vertex 0: positive wherever a face reaches, 0 at isolated vertices.
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
    delta[0] = 1.0;
    const Eigen::VectorXd u = llt.solve(delta);
    std::vector<char> in_face(static_cast<size_t>(n), 0);
    for (int32_t v : m.face_vertices) in_face[v] = 1;
    for (int32_t v = 0; v < n; ++v) {
      CAPTURE(v);
      if (in_face[v])
        CHECK(u[v] > 0.0);
      else
        CHECK(u[v] == 0.0);
    }
    CHECK(R.isolated_vertices == (kind == PlantedDefect::Unreferenced ? 4 : 0));
    // The defect is also what the detection reports.
    const MeshDefects d = detect_mesh_defects(m);
    switch (kind) {
      case PlantedDefect::Fin: CHECK(d.non_manifold_edges == 4); break;
      case PlantedDefect::Bowtie: CHECK(d.non_manifold_vertices == 4); break;
      case PlantedDefect::ZeroArea: CHECK(d.zero_area_faces == 4); break;
      case PlantedDefect::Needle: CHECK(d.needle_faces >= 4); break;
      case PlantedDefect::FlippedPatch: CHECK(d.inconsistent_orientation_edges > 0); break;
      case PlantedDefect::Unreferenced: CHECK(d.unreferenced_vertices == 4); break;
      case PlantedDefect::DuplicateFace: CHECK(d.non_manifold_edges == 12); break;
    }
    CHECK(d.any());
  }
}

TEST_CASE("robust Laplacian: the clean icosphere has no defects; soups with repeated ids and no faces") {
  CHECK(!detect_mesh_defects(make_icosphere(2)).any());
  // A face repeating a vertex id is dropped: its vertices only there are isolated.
  Mesh m;
  m.add_vertex(0, 0, 0), m.add_vertex(1, 0, 0), m.add_vertex(0, 1, 0), m.add_vertex(5, 5, 5), m.add_vertex(6, 5, 5);
  m.add_triangle(0, 1, 2);
  m.add_triangle(3, 3, 4);
  const RobustOperators R = robust_laplacian(m);
  CHECK(R.isolated_vertices == 2);
  CHECK(R.mass[3] == doctest::Approx(0.5 / 3));  // the mean mass of the others
  CHECK(R.mass[0] == doctest::Approx(0.5 / 3));
  const MeshDefects d = detect_mesh_defects(m);
  CHECK(d.zero_area_faces == 1);
  CHECK(d.first_zero_area_face == 1);
  // No faces at all: identity mass, zero Laplacian.
  Mesh e;
  e.add_vertex(0, 0, 0), e.add_vertex(1, 0, 0);
  const RobustOperators Re = robust_laplacian(e);
  CHECK(Re.isolated_vertices == 2);
  CHECK(Re.mass[0] == 1.0);
  CHECK(Re.L.values[0] == 0.0);
}

TEST_CASE("robust Laplacian: the library's ordering, factorization and solve take M - tL of every planted defect") {
  const Mesh clean = make_icosphere(3);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const PlantedDefect kind = static_cast<PlantedDefect>(k);
    CAPTURE(planted_defect_name(kind));
    const Mesh m = plant_mesh_defect(clean, kind, 6);
    const RobustOperators R = robust_laplacian(m);
    const double h = mean_edge_length(m);
    const CscMatrix A = combine_same_pattern(1.0, R.M, -h * h, R.L);
    const NumericFactor F = factorize(analyze(A, order_matrix(A)), A);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1, 1);
    std::vector<double> b(static_cast<size_t>(A.ncols)), x, Ax(b.size());
    for (double& v : b) v = U(rng);
    x = b;
    solve(F, x);
    symmetric_multiply(A, x.data(), Ax.data());
    double r = 0, nb = 0;
    for (size_t i = 0; i < b.size(); ++i) r += (Ax[i] - b[i]) * (Ax[i] - b[i]), nb += b[i] * b[i];
    CHECK(std::sqrt(r / nb) <= 1e-10);
  }
}
