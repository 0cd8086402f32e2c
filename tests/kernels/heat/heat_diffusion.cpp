// Tests for kernels/heat/heat_diffusion (thesis §3.2): the mesh paths order the
// operator's pattern beside the assembly and the mesh checks; they must give
// the factor the assembled-matrix path gives, solve M - tL against a dense
// oracle, and refuse bad meshes with the checks' own messages.
#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <cmath>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_full.hpp"

using namespace locus;

namespace {

std::string refusal(const Mesh& m) {
  try {
    (void)prepare_heat_diffusion(m, 1.0, 0.0, {});
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::BadInput);
    return e.what();
  }
  return "";
}

std::string check_message(const Mesh& m) {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  try {
    check_requirements(m, req);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("heat diffusion: the mesh paths give the assembled operator's factor, which solves M - tL") {
  const Mesh m = make_icosphere(3);
  const double h = mean_edge_length(m), t = 2.0 * h * h;
  const HeatDiffusion from_mesh = prepare_heat_diffusion(m, 2.0, 0.0, {});
  const HeatDiffusion from_derived = prepare_heat_diffusion(m, derive_mesh(m), 2.0, 0.0, {});
  const CscMatrix A = heat_operator(m, t);
  const HeatDiffusion from_matrix = prepare_heat_diffusion(A, lumped_mass(m), h, t, {});
  CHECK(from_mesh.t == doctest::Approx(t).epsilon(1e-15));
  for (const HeatDiffusion* H : {&from_mesh, &from_derived}) {
    CHECK(H->factor.symbolic->perm == from_matrix.factor.symbolic->perm);
    CHECK(H->factor.values == from_matrix.factor.values);
    CHECK(H->mass == from_matrix.mass);
  }
  // Independent oracle: a dense solve of the symmetric operator.
  const int n = A.ncols;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int64_t p = A.colptr[j]; p < A.colptr[j + 1]; ++p) {
      D(A.rowind[p], j) = A.values[p];
      D(j, A.rowind[p]) = A.values[p];
    }
  std::vector<double> b(n), x(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.37 * i) + (i == 5 ? 1.0 : 0.0);
  x = b;
  std::vector<double> work(solve_work_size(from_mesh.factor, 1));
  solve(from_mesh.factor, x, work);
  const Eigen::VectorXd want = D.ldlt().solve(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
  double err = 0;
  for (int i = 0; i < n; ++i) err = std::max(err, std::abs(x[i] - want[i]));
  CHECK(err < 1e-12 * want.cwiseAbs().maxCoeff());
}

TEST_CASE("heat diffusion: bad meshes are refused with the checks' messages while the edges are ordered") {
  // Three triangles on one edge (non-manifold).
  Mesh fan;
  for (double p : {0.0, 1.0}) fan.add_vertex(p, 0, 0);
  fan.add_vertex(0.5, 1, 0);
  fan.add_vertex(0.5, -1, 0);
  fan.add_vertex(0.5, 0, 1);
  for (int32_t c : {2, 3, 4}) fan.add_face(std::vector<int32_t>{0, 1, c});
  // A zero-area face (a corner repeated in space).
  Mesh flat = make_icosphere(1);
  flat.x[flat.face_vertices[1]] = flat.x[flat.face_vertices[0]];
  flat.y[flat.face_vertices[1]] = flat.y[flat.face_vertices[0]];
  flat.z[flat.face_vertices[1]] = flat.z[flat.face_vertices[0]];
  // Quads.
  const Mesh quads = make_quad_torus(8, 6);
  for (const Mesh* m : std::vector<const Mesh*>{&fan, &flat, &quads}) {
    const std::string want = check_message(*m);
    REQUIRE(!want.empty());
    CHECK(refusal(*m) == want);
  }
  // Face indices out of range: the arrays' check, before anything is built.
  Mesh broken = make_icosphere(1);
  broken.face_vertices[4] = 1000;
  CHECK(refusal(broken).find("1000") != std::string::npos);
}
