// Tests for pipelines/deform: closed-form checks on a planar grid (the cotan
// Laplacian reproduces affine maps at interior vertices, so fixing every known
// vertex by an affine map moves every free vertex by the same map, for the
// Laplacian and — away from the mesh border — the bi-Laplacian energy;
// translating handle and outside together translates everything), an Eigen
// sparse solve of the constrained system assembled here from cotan_laplacian,
// agreement with a from-scratch factor of A_FF, fixed vertices bit-identical,
// faces untouched, and bad regions.
#include "locus/pipelines/deform/deform.hpp"

#include <Eigen/SparseCholesky>
#include <doctest/doctest.h>

#include <cmath>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

// Vertex of the grid nearest to (px, py).
int32_t nearest(const Mesh& m, double px, double py) {
  int32_t best = 0;
  double bd = HUGE_VAL;
  for (int32_t v = 0; v < m.num_vertices(); ++v) {
    const double d = (m.x[v] - px) * (m.x[v] - px) + (m.y[v] - py) * (m.y[v] - py);
    if (d < bd) { bd = d; best = v; }
  }
  return best;
}

struct Run {
  DeformRegion region;
  DeformSystem sys;
  Mesh out;
  DeformSolveStats st;
};

void check_fixed_bit_identical(const Mesh& rest, const Mesh& out, const DeformRegion& r) {
  std::vector<uint8_t> in_roi(rest.num_vertices(), 0);
  for (int32_t v : r.roi) in_roi[v] = 1;
  int64_t differ = 0;
  for (int32_t v = 0; v < rest.num_vertices(); ++v)
    if (!in_roi[v] && (out.x[v] != rest.x[v] || out.y[v] != rest.y[v] || out.z[v] != rest.z[v])) ++differ;
  CHECK(differ == 0);
  CHECK(out.face_vertices == rest.face_vertices);
  CHECK(out.face_offsets == rest.face_offsets);
}

}  // namespace

TEST_CASE("planar grid: affine boundary data give the affine map everywhere (Laplacian and bi-Laplacian)") {
  const Mesh grid = make_grid(30, 0.3, 5);  // irregular diagonals: cotan weights vary
  const Adjacency adj = vertex_adjacency(grid);
  const int32_t center = nearest(grid, 0.5, 0.5);
  for (DeformEnergy energy : {DeformEnergy::Laplacian, DeformEnergy::Bilaplacian}) {
    CAPTURE(deform_energy_name(energy));
    const DeformOperator op = prepare_deform_operator(grid, energy);
    // 30% of the vertices around the center stay two rings away from the border.
    const DeformRegion region = make_deform_region(adj, center, 0.3, nearest(grid, 0.55, 0.5), 1);
    for (int32_t v : region.roi) REQUIRE((grid.x[v] > 0.07 && grid.x[v] < 0.93 && grid.y[v] > 0.07 && grid.y[v] < 0.93));
    const DeformSystem sys = prepare_deform_system(op, region);
    CHECK(sys.sub.stats.columns_updated_fraction < 1.0);

    // Translation: handle and outside moved by t.
    const std::array<double, 3> t{0.25, -0.125, 0.75};
    Mesh shifted = grid;
    for (int32_t v = 0; v < grid.num_vertices(); ++v) { shifted.x[v] += t[0]; shifted.y[v] += t[1]; shifted.z[v] += t[2]; }
    Mesh out;
    const DeformSolveStats st = solve_deformation(sys.sub.factor, sys, grid, shifted, out);
    double worst = 0;
    for (int32_t v = 0; v < grid.num_vertices(); ++v)
      worst = std::max({worst, std::abs(out.x[v] - grid.x[v] - t[0]), std::abs(out.y[v] - grid.y[v] - t[1]),
                        std::abs(out.z[v] - grid.z[v] - t[2])});
    CHECK(worst <= 1e-10);
    CHECK(st.residual <= 1e-10);

    // A general affine map of the known vertices (z gets a tilt): reproduced at the free ones.
    Mesh affine = grid;
    auto map = [](double x, double y, double z, int c) {
      return c == 0 ? 1.1 * x + 0.2 * y + 0.05 : c == 1 ? -0.3 * x + 0.9 * y : z + 0.4 * x - 0.7 * y + 0.1;
    };
    for (int32_t v = 0; v < grid.num_vertices(); ++v) {
      affine.x[v] = map(grid.x[v], grid.y[v], grid.z[v], 0);
      affine.y[v] = map(grid.x[v], grid.y[v], grid.z[v], 1);
      affine.z[v] = map(grid.x[v], grid.y[v], grid.z[v], 2);
    }
    solve_deformation(sys.sub.factor, sys, grid, affine, out);
    worst = 0;
    for (int32_t v : region.free)
      worst = std::max({worst, std::abs(out.x[v] - affine.x[v]), std::abs(out.y[v] - affine.y[v]),
                        std::abs(out.z[v] - affine.z[v])});
    CHECK(worst <= 1e-10);
  }
}

TEST_CASE("icosphere: the deformation solves the constrained system (Eigen oracle), fixed vertices bit-identical") {
  const Mesh sphere = make_icosphere(4);
  const Adjacency adj = vertex_adjacency(sphere);
  const std::array<double, 3> offset{0.1, 0.3, -0.2};
  for (DeformEnergy energy : {DeformEnergy::Laplacian, DeformEnergy::Bilaplacian}) {
    CAPTURE(deform_energy_name(energy));
    const DeformOperator op = prepare_deform_operator(sphere, energy);
    const DeformRegion region = make_deform_region(adj, 7, 0.25, 7, 2);
    CHECK(region.handle.size() > 1);
    const DeformSystem sys = prepare_deform_system(op, region);
    Mesh out;
    solve_deformation(sys.sub.factor, sys, sphere, handle_target(sphere, region, offset), out);
    check_fixed_bit_identical(sphere, out, region);
    // A zero offset keeps the rest shape (displacement formulation).
    Mesh still;
    solve_deformation(sys.sub.factor, sys, sphere, sphere, still);
    CHECK(still.x == sphere.x);
    CHECK(still.z == sphere.z);
    for (int32_t v : region.handle) {
      CHECK(out.x[v] == sphere.x[v] + offset[0]);
      CHECK(out.z[v] == sphere.z[v] + offset[2]);
    }

    // Oracle: E = -L_C (or L_C M^{-1} L_C) built here with Eigen, E_FF d_F = -E_FB d_B.
    const CscMatrix Lc = cotan_laplacian(sphere);
    std::vector<Eigen::Triplet<double>> t;
    for (int32_t j = 0; j < Lc.ncols; ++j)
      for (int64_t p = Lc.colptr[j]; p < Lc.colptr[j + 1]; ++p) {
        t.emplace_back(Lc.rowind[p], j, -Lc.values[p]);
        if (Lc.rowind[p] != j) t.emplace_back(j, Lc.rowind[p], -Lc.values[p]);
      }
    const int32_t n = sphere.num_vertices();
    Eigen::SparseMatrix<double> Lp(n, n);
    Lp.setFromTriplets(t.begin(), t.end());
    Eigen::SparseMatrix<double> E = Lp;
    if (energy == DeformEnergy::Bilaplacian) {
      const auto M = lumped_mass(sphere);
      Eigen::VectorXd minv(n);
      for (int32_t i = 0; i < n; ++i) minv[i] = 1.0 / M[i];
      E = Lp * minv.asDiagonal() * Lp;
    }
    std::vector<int32_t> pos(n, -1);
    for (size_t a = 0; a < region.free.size(); ++a) pos[region.free[a]] = static_cast<int32_t>(a);
    const auto nf = static_cast<Eigen::Index>(region.free.size());
    std::vector<Eigen::Triplet<double>> tf;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nf, 3);
    for (int k = 0; k < E.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(E, k); it; ++it) {
        const int32_t i = static_cast<int32_t>(it.row()), j = static_cast<int32_t>(it.col());
        if (pos[i] < 0) continue;
        if (pos[j] >= 0) tf.emplace_back(pos[i], pos[j], it.value());
        else {
          rhs(pos[i], 0) -= it.value() * (out.x[j] - sphere.x[j]);
          rhs(pos[i], 1) -= it.value() * (out.y[j] - sphere.y[j]);
          rhs(pos[i], 2) -= it.value() * (out.z[j] - sphere.z[j]);
        }
      }
    Eigen::SparseMatrix<double> Eff(nf, nf);
    Eff.setFromTriplets(tf.begin(), tf.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Eff);
    REQUIRE(ldlt.info() == Eigen::Success);
    const Eigen::MatrixXd X = ldlt.solve(rhs);
    double diff = 0, scale = 0;
    for (Eigen::Index a = 0; a < nf; ++a) {
      const int32_t v = region.free[static_cast<size_t>(a)];
      diff = std::max({diff, std::abs(X(a, 0) - (out.x[v] - sphere.x[v])), std::abs(X(a, 1) - (out.y[v] - sphere.y[v])),
                       std::abs(X(a, 2) - (out.z[v] - sphere.z[v]))});
      scale = std::max(scale, X.row(a).cwiseAbs().maxCoeff());
    }
    CHECK(diff <= 1e-8 * scale);

    // The same deformation with a factor of A_FF from scratch (METIS on A_FF).
    const CscMatrix& Aff = sys.sub.A_sub;
    const NumericFactor Fs = factorize(analyze(Aff, order_matrix(Aff)), Aff);
    Mesh out2;
    solve_deformation(Fs, sys, sphere, handle_target(sphere, region, offset), out2);
    double d2 = 0;
    for (int32_t v = 0; v < n; ++v)
      d2 = std::max({d2, std::abs(out2.x[v] - out.x[v]), std::abs(out2.y[v] - out.y[v]), std::abs(out2.z[v] - out.z[v])});
    CHECK(d2 <= 1e-10 * scale);
  }
}

TEST_CASE("bad regions are usage errors") {
  const Mesh sphere = make_icosphere(2);
  const Adjacency adj = vertex_adjacency(sphere);
  const int32_t n = sphere.num_vertices();
  CHECK_THROWS_AS(make_deform_region(adj, n, 0.2, 0, 1), Error);        // seed out of range
  CHECK_THROWS_AS(make_deform_region(adj, 0, 0.0, 0, 1), Error);        // empty ROI
  CHECK_THROWS_AS(make_deform_region(adj, 0, 1.5, 0, 1), Error);        // fraction > 1
  CHECK_THROWS_AS(make_deform_region(adj, 0, 0.05, 0, 10), Error);      // handle covers the ROI
  const std::vector<int32_t> far = grow_ring_vertices(adj, 0, n);       // last vertex reached from 0
  CHECK_THROWS_AS(make_deform_region(adj, 0, 0.1, far.back(), 0), Error);  // handle outside the ROI
  try {
    make_deform_region(adj, 0, 0.1, far.back(), 0);
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadUsage);
  }
  CHECK_THROWS_AS(parse_deform_energy("elastic"), Error);
}
