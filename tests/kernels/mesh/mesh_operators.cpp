// Tests for kernels/src/mesh/mesh_operators.cpp.
// Oracles: a dense cotan matrix assembled independently from angles (atan2) per
// triangle (eq. 3.5), triangle areas (eq. 3.6), analytic facts (constants in the
// kernel, linear precision on planar meshes, the sphere's area 4 pi r^2 and mean
// curvature normal (2/r) n), and Eigen's dense LLT / eigen solver and sparse
// SimplicialLLT for definiteness and solve residuals.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

using namespace locus;

namespace {

Eigen::MatrixXd dense_from_lower(const CscMatrix& A) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(A.nrows, A.ncols);
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      D(A.rowind[p], j) = A.values[p];
      D(j, A.rowind[p]) = A.values[p];
    }
  return D;
}

// Cotan matrix from angles: for each triangle and each corner angle theta, add
// cot(theta)/2 to the entry of the opposite edge (both triangles of an edge add up).
Eigen::MatrixXd dense_cotan_oracle(const Mesh& m) {
  const int32_t n = m.num_vertices();
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      const Eigen::Vector3d u(m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]);
      const Eigen::Vector3d w(m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]);
      const double theta = std::atan2(u.cross(w).norm(), u.dot(w));
      const double half_cot = 0.5 / std::tan(theta);
      L(b, c) += half_cot;
      L(c, b) += half_cot;
    }
  }
  for (int32_t i = 0; i < n; ++i) L(i, i) = -(L.row(i).sum());
  return L;
}

Eigen::VectorXd area_third_oracle(const Mesh& m) {
  Eigen::VectorXd M = Eigen::VectorXd::Zero(m.num_vertices());
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
    // Heron's formula: an area computation that shares nothing with the kernel's cross product.
    const double la = std::hypot(m.x[b] - m.x[c], m.y[b] - m.y[c], m.z[b] - m.z[c]);
    const double lb = std::hypot(m.x[a] - m.x[c], m.y[a] - m.y[c], m.z[a] - m.z[c]);
    const double lc = std::hypot(m.x[a] - m.x[b], m.y[a] - m.y[b], m.z[a] - m.z[b]);
    const double s = 0.5 * (la + lb + lc);
    const double area = std::sqrt(std::max(0.0, s * (s - la) * (s - lb) * (s - lc)));
    M[a] += area / 3;
    M[b] += area / 3;
    M[c] += area / 3;
  }
  return M;
}

std::vector<double> multiply(const CscMatrix& A, ConstView<double> x) {
  std::vector<double> y(x.size());
  symmetric_multiply(A, x.data(), y.data());
  return y;
}

double max_abs_diagonal(const CscMatrix& A) {
  double d = 0;
  for (int32_t j = 0; j < A.ncols; ++j) d = std::max(d, std::fabs(A.values[A.colptr[j]]));
  return d;
}

std::vector<char> boundary_flags(const Mesh& m) {
  std::vector<char> on(m.num_vertices(), 0);
  for (const auto& loop : boundary_loops(m))
    for (int32_t v : loop) on[v] = 1;
  return on;
}

// Worst relative residual |A x - b| / |b| of Eigen's sparse Cholesky over random b.
double cholesky_residual(const CscMatrix& A) {
  std::vector<Eigen::Triplet<double>> t;
  for (int32_t j = 0; j < A.ncols; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) t.emplace_back(A.rowind[p], j, A.values[p]);
  Eigen::SparseMatrix<double> S(A.nrows, A.ncols);
  S.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt(S);
  REQUIRE(llt.info() == Eigen::Success);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  double worst = 0;
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<double> b(A.nrows);
    for (double& v : b) v = U(rng);
    const Eigen::VectorXd x = llt.solve(Eigen::Map<Eigen::VectorXd>(b.data(), A.nrows));
    const std::vector<double> ax = multiply(A, std::vector<double>(x.data(), x.data() + A.nrows));
    double r2 = 0, b2 = 0;
    for (int32_t i = 0; i < A.nrows; ++i) {
      r2 += (ax[i] - b[i]) * (ax[i] - b[i]);
      b2 += b[i] * b[i];
    }
    worst = std::max(worst, std::sqrt(r2 / b2));
  }
  return worst;
}

}  // namespace

TEST_CASE("cotan Laplacian equals the dense angle-based oracle (eq. 3.5)") {
  for (const Mesh& m : {make_icosphere(1, 1.7), make_random_sphere(60, 2), make_disk(3, 0.5, 1), make_torus(7, 5)}) {
    const CscMatrix L = cotan_laplacian(m);
    const Eigen::MatrixXd D = dense_from_lower(L), R = dense_cotan_oracle(m);
    CHECK((D - R).cwiseAbs().maxCoeff() <= 1e-12 * R.cwiseAbs().maxCoeff());
    CHECK(L.nrows == m.num_vertices());
    // Negative diagonal, -L positive semidefinite: smallest eigenvalue of -L is 0 (constants).
    for (int32_t j = 0; j < L.ncols; ++j) CHECK(L.values[L.colptr[j]] < 0);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(-R).eigenvalues();
    CHECK(std::fabs(ev[0]) <= 1e-10 * ev[ev.size() - 1]);
  }
}

TEST_CASE("L_C annihilates constants and all operators share one sorted lower pattern") {
  for (const Mesh& m : {make_icosphere(3), make_random_sphere(2000, 9), make_grid(9, 0.5, 1), make_torus(20, 9)}) {
    const CscMatrix L = cotan_laplacian(m);
    const std::vector<double> l1 = multiply(L, std::vector<double>(m.num_vertices(), 1.0));
    double worst = 0;
    for (double v : l1) worst = std::max(worst, std::fabs(v));
    CHECK(worst <= 1e-13 * max_abs_diagonal(L));
    const Edges e = unique_edges(m);
    CHECK(L.nnz() == m.num_vertices() + static_cast<int64_t>(e.e0.size()));
    // Column j: the diagonal first, then its larger neighbors ascending (edges (j, k)).
    size_t k = 0;
    for (int32_t j = 0; j < L.ncols; ++j) {
      REQUIRE(L.colptr[j + 1] > L.colptr[j]);
      CHECK(L.rowind[L.colptr[j]] == j);
      for (int64_t p = L.colptr[j] + 1; p < L.colptr[j + 1]; ++p, ++k) {
        CHECK(e.e0[k] == j);
        CHECK(e.e1[k] == L.rowind[p]);
      }
    }
    CHECK(k == e.e0.size());
    for (const CscMatrix& A : {mass_matrix_as_csc(m), heat_operator(m, 0.1), regularized_laplacian(m)}) {
      CHECK(A.colptr == L.colptr);
      CHECK(A.rowind == L.rowind);
    }
  }
}

TEST_CASE("linear precision: L_C x = L_C y = 0 at interior vertices of planar meshes") {
  for (const Mesh& m : {make_grid(10), make_grid(10, 0.5, 7), make_disk(8), make_disk(8, 0.4, 3)}) {
    const CscMatrix L = cotan_laplacian(m);
    const std::vector<char> boundary = boundary_flags(m);
    const std::vector<double> lx = multiply(L, m.x), ly = multiply(L, m.y);
    const double scale = max_abs_diagonal(L);
    int32_t interior = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      if (boundary[i]) continue;
      ++interior;
      CHECK(std::fabs(lx[i]) <= 1e-13 * scale);
      CHECK(std::fabs(ly[i]) <= 1e-13 * scale);
    }
    CHECK(interior > 0);
    // Not trivially zero: on the boundary the same products do not vanish.
    double on_boundary = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i)
      if (boundary[i]) on_boundary = std::max(on_boundary, std::fabs(lx[i]));
    CHECK(on_boundary > 1e-3 * scale * (m.x[1] - m.x[0] == 0 ? 1 : std::fabs(m.x[1] - m.x[0])));
  }
}

TEST_CASE("lumped mass (eq. 3.6): a third of the incident areas, total = surface area") {
  for (const Mesh& m : {make_icosphere(2, 0.5), make_random_sphere(300, 4), make_disk(5, 0.3, 2)}) {
    const auto M = lumped_mass(m);
    const Eigen::VectorXd R = area_third_oracle(m);
    for (int32_t i = 0; i < m.num_vertices(); ++i) CHECK(M[i] == doctest::Approx(R[i]).epsilon(1e-10));
  }
  // Unit square grid: total exactly 1; an interior vertex of the regular pattern has
  // six triangles of area h^2/2, i.e. mass h^2.
  const int32_t n = 16;
  const auto g = lumped_mass(make_grid(n));
  double total = 0;
  for (double v : g) total += v;
  CHECK(total == doctest::Approx(1.0).epsilon(1e-14));
  CHECK(g[5 * (n + 1) + 7] == doctest::Approx(1.0 / (n * n)).epsilon(1e-14));
  // Sphere of radius r: the inscribed icospheres' area increases towards 4 pi r^2.
  const double r = 1.5, exact = 4 * M_PI * r * r;
  double previous_error = exact;
  for (int level = 1; level <= 5; ++level) {
    double area = 0;
    for (double v : lumped_mass(make_icosphere(level, r))) area += v;
    const double error = exact - area;
    CHECK(error > 0);
    CHECK(error < 0.3 * previous_error);
    previous_error = error;
  }
  CHECK(previous_error < 2e-3 * exact);
  // The CSC form holds the same numbers on its diagonal and zeros elsewhere.
  const Mesh s = make_icosphere(2);
  const CscMatrix Mc = mass_matrix_as_csc(s);
  const auto Md = lumped_mass(s);
  for (int32_t j = 0; j < Mc.ncols; ++j)
    for (int64_t p = Mc.colptr[j]; p < Mc.colptr[j + 1]; ++p) CHECK(Mc.values[p] == (p == Mc.colptr[j] ? Md[j] : 0.0));
}

TEST_CASE("mean-curvature normal approaches (2/r) n on icospheres; points outward") {
  // The area-weighted (mass) RMS error halves with every level (O(h)); the maximum
  // does not converge: at the 12 valence-5 vertices the barycentric area is not the
  // vertex's Voronoi area, which leaves |Hn| about 14.6% off there at every level.
  const double r = 2.0;
  double previous_rms = 1e300, previous_angle = 1e300;
  for (int level = 1; level <= 5; ++level) {
    const Mesh m = make_icosphere(level, r);
    const auto hn = mean_curvature_normals(m), n = area_weighted_normals(m), M = lumped_mass(m);
    double sq = 0, area = 0, angle = 0, mean_magnitude = 0;
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      double d2 = 0, mag2 = 0, dot = 0;
      for (int k = 0; k < 3; ++k) {
        d2 += std::pow(hn[3 * i + k] - (2.0 / r) * n[3 * i + k], 2);
        mag2 += hn[3 * i + k] * hn[3 * i + k];
        dot += hn[3 * i + k] * n[3 * i + k];
      }
      sq += M[i] * d2;
      area += M[i];
      mean_magnitude += M[i] * std::sqrt(mag2);
      angle = std::max(angle, std::acos(std::min(1.0, dot / std::sqrt(mag2))));
    }
    const double rms = std::sqrt(sq / area) / (2.0 / r);
    MESSAGE("icosphere level " << level << ": RMS |Hn - (2/r) n| / (2/r) = " << rms << ", max angle " << angle);
    CHECK(rms < 0.6 * previous_rms);
    if (level >= 4) CHECK(angle < 0.6 * previous_angle);
    CHECK(mean_magnitude / area == doctest::Approx(2.0 / r).epsilon(1e-3));
    previous_rms = rms;
    previous_angle = angle;
  }
  CHECK(previous_rms < 0.005);
  CHECK(previous_angle < 0.002);
  // Outward on an irregular convex surface.
  const Mesh s = make_random_sphere(3000, 8);
  const auto hn = mean_curvature_normals(s);
  for (int32_t i = 0; i < s.num_vertices(); ++i)
    CHECK(hn[3 * i] * s.x[i] + hn[3 * i + 1] * s.y[i] + hn[3 * i + 2] * s.z[i] > 0);
}

TEST_CASE("area-weighted normals: unit, radial on spheres, outward on the quad torus") {
  const Mesh m = make_icosphere(3, 3.0);
  const auto n = area_weighted_normals(m);
  for (int32_t i = 0; i < m.num_vertices(); ++i) {
    const double len = std::sqrt(n[3 * i] * n[3 * i] + n[3 * i + 1] * n[3 * i + 1] + n[3 * i + 2] * n[3 * i + 2]);
    CHECK(len == doctest::Approx(1.0).epsilon(1e-14));
    CHECK((n[3 * i] * m.x[i] + n[3 * i + 1] * m.y[i] + n[3 * i + 2] * m.z[i]) / 3.0 > 0.999);
  }
  const double R = 1.0;
  const Mesh q = make_quad_torus(24, 12, R, 0.4);
  const auto nq = area_weighted_normals(q);
  for (int32_t i = 0; i < q.num_vertices(); ++i) {
    const double rho = std::hypot(q.x[i], q.y[i]);
    const double ox = q.x[i] - R * q.x[i] / rho, oy = q.y[i] - R * q.y[i] / rho, oz = q.z[i];
    // Close to the direction away from the core circle (not exactly: the quads on the
    // outer side of a vertex are wider than those on its inner side).
    CHECK((nq[3 * i] * ox + nq[3 * i + 1] * oy + nq[3 * i + 2] * oz) / 0.4 > 0.999);
  }
}

TEST_CASE("heat operator M - tL is positive definite and equals its definition") {
  const Mesh m = make_icosphere(2);
  const Eigen::MatrixXd L = dense_cotan_oracle(m);
  const Eigen::VectorXd M = area_third_oracle(m);
  for (double t : {0.0, 1e-3, 1.0, 1e3}) {
    const CscMatrix H = heat_operator(m, t);
    const Eigen::MatrixXd D = dense_from_lower(H);
    const Eigen::MatrixXd R = Eigen::MatrixXd(M.asDiagonal()) - t * L;
    CHECK((D - R).cwiseAbs().maxCoeff() <= 1e-10 * R.cwiseAbs().maxCoeff());
    Eigen::LLT<Eigen::MatrixXd> llt(D);
    CHECK(llt.info() == Eigen::Success);
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(D).eigenvalues()[0] > 0);
  }
  CHECK_THROWS_AS(heat_operator(m, -1.0), Error);
  CHECK_THROWS_AS(heat_operator(m, std::nan("")), Error);
}

TEST_CASE("regularized Laplacian: -L + eps M, Cholesky residual <= 1e-10 whatever the units") {
  const Mesh ico = make_icosphere(4);
  {
    const CscMatrix A = regularized_laplacian(ico, 1e-3);
    const CscMatrix L = cotan_laplacian(ico);
    const auto M = lumped_mass(ico);
    double tl = 0, tm = 0;
    for (int32_t j = 0; j < L.ncols; ++j) tl -= L.values[L.colptr[j]], tm += M[j];
    const double eps = 1e-3 * tl / tm;
    for (int32_t j = 0; j < A.ncols; ++j)
      for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p)
        CHECK(A.values[p] == doctest::Approx(-L.values[p] + (p == A.colptr[j] ? eps * M[j] : 0.0)).epsilon(1e-14));
  }
  std::vector<std::pair<std::string, Mesh>> meshes = {{"icosphere(4)", ico}, {"random sphere 5000", make_random_sphere(5000, 1)}};
  const std::string path = std::string(LOCUS_MESH_CACHE_DIR) + "/armadillo.off";
  if (std::filesystem::exists(path)) {
    Mesh arm = read_mesh(path);
    double area = 0;
    for (double v : lumped_mass(arm)) area += v;
    CHECK(area > 3e4);  // the armadillo's natural units
    Mesh unit = arm;
    for (auto* c : {&unit.x, &unit.y, &unit.z})
      for (double& v : *c) v /= std::sqrt(area);
    meshes.emplace_back("armadillo", std::move(arm));
    meshes.emplace_back("armadillo scaled to unit area", std::move(unit));
  } else {
    MESSAGE("armadillo part skipped: " << path << " is missing");
  }
  for (const auto& [name, m] : meshes) {
    const double res = cholesky_residual(regularized_laplacian(m));
    MESSAGE(name << ": relative residual " << res);
    CHECK(res <= 1e-10);
  }
  CHECK_THROWS_AS(regularized_laplacian(ico, 0.0), Error);
}

TEST_CASE("operators reject polygon meshes, zero-area triangles and bad indices") {
  Mesh q = make_quad_torus(4, 4);
  q.source = "quads.obj";
  CHECK_THROWS_WITH_AS(cotan_laplacian(q), "quads.obj: face 0 has 4 vertices; the cotan Laplacian needs a triangle mesh",
                       Error);
  CHECK_THROWS_AS(lumped_mass(q), Error);
  CHECK_THROWS_AS(heat_operator(q, 1.0), Error);
  CHECK_THROWS_AS(mean_curvature_normals(q), Error);
  Mesh z;
  for (auto p : {std::array<double, 3>{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}}) z.add_vertex(p[0], p[1], p[2]);
  z.add_triangle(0, 1, 2);
  z.add_triangle(0, 3, 1);
  z.source = "flat.off";
  CHECK_THROWS_WITH_AS(cotan_laplacian(z), "flat.off: face 1 has zero area; the cotan Laplacian needs non-degenerate triangles",
                       Error);
  try {
    regularized_laplacian(z);
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
  }
  Mesh nan = make_icosphere(1);
  nan.y[7] = std::nan("");
  CHECK_THROWS_WITH_AS(cotan_laplacian(nan), "mesh: vertex 7 has a non-finite coordinate; the cotan Laplacian needs finite positions", Error);
  CHECK_THROWS_AS(lumped_mass(nan), Error);
  Mesh bad = make_icosphere(0);
  bad.face_vertices[5] = 12;
  bad.f0.clear(), bad.f1.clear(), bad.f2.clear();
  CHECK_THROWS_AS(cotan_laplacian(bad), Error);
  CHECK_THROWS_AS(area_weighted_normals(bad), Error);
  CHECK_THROWS_AS(mass_matrix_as_csc(bad), Error);
}
