// Tests for kernels/src/mesh/manifold_sheets.cpp. Oracles: analyze_mesh (the
// checker every pipeline's requirements use) on the sheets, the planted defects'
// known counts, the sphere's area (independent of how the faces are cut), and
// positions recomputed from the barycentric map back to the input faces.
#include <doctest/doctest.h>

#include <cmath>

#include "locus/kernels/mesh/manifold_sheets.hpp"
#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

using namespace locus;

namespace {

double area(const Mesh& m) {
  double a = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t i = m.f0[f], j = m.f1[f], k = m.f2[f];
    const double ux = m.x[j] - m.x[i], uy = m.y[j] - m.y[i], uz = m.z[j] - m.z[i];
    const double wx = m.x[k] - m.x[i], wy = m.y[k] - m.y[i], wz = m.z[k] - m.z[i];
    const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
    a += 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
  }
  return a;
}

// Every sheet corner, mapped through corner_bary into its input face, lands on its own position.
double max_map_error(const Mesh& in, const ManifoldSheets& s) {
  double worst = 0;
  for (int32_t f = 0; f < s.mesh.num_faces(); ++f) {
    const int32_t g = s.face_of[f];
    const int32_t iv[3] = {in.f0[g], in.f1[g], in.f2[g]};
    const int32_t sv[3] = {s.mesh.f0[f], s.mesh.f1[f], s.mesh.f2[f]};
    for (int k = 0; k < 3; ++k) {
      double p[3] = {0, 0, 0};
      for (int j = 0; j < 3; ++j) {
        const double b = s.corner_bary[f][3 * k + j];
        p[0] += b * in.x[iv[j]], p[1] += b * in.y[iv[j]], p[2] += b * in.z[iv[j]];
      }
      worst = std::max({worst, std::abs(p[0] - s.mesh.x[sv[k]]), std::abs(p[1] - s.mesh.y[sv[k]]),
                        std::abs(p[2] - s.mesh.z[sv[k]])});
    }
  }
  return worst;
}

void check_clean(const ManifoldSheets& s) {
  const MeshReport r = analyze_mesh(s.mesh);
  CHECK(r.manifold);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.non_manifold_vertices == 0);
  CHECK(r.degenerate_faces == 0);
  CHECK(r.unreferenced_vertices == 0);
  CHECK_NOTHROW(check_requirements(s.mesh, MeshRequirements{}));
}

}  // namespace

TEST_CASE("manifold sheets: a clean mesh is its own sheets") {
  const Mesh m = make_icosphere(2);
  const ManifoldSheets s = manifold_sheets(m);
  CHECK_FALSE(s.changed());
  REQUIRE(s.mesh.num_vertices() == m.num_vertices());
  REQUIRE(s.mesh.num_faces() == m.num_faces());
  for (int32_t v = 0; v < m.num_vertices(); ++v) CHECK(s.vertex_of[v] == v);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    CHECK(s.mesh.f0[f] == m.f0[f]);
    CHECK(s.mesh.f1[f] == m.f1[f]);
    CHECK(s.mesh.f2[f] == m.f2[f]);
  }
}

TEST_CASE("manifold sheets: every planted defect kind gives a clean manifold, oriented mesh") {
  const Mesh clean = make_icosphere(3);
  const double clean_area = area(clean);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const auto kind = static_cast<PlantedDefect>(k);
    CAPTURE(planted_defect_name(kind));
    const Mesh m = plant_mesh_defect(clean, kind, 8);
    const ManifoldSheets s = manifold_sheets(m);
    check_clean(s);
    CHECK(max_map_error(m, s) < 1e-12);
    const MeshReport r = analyze_mesh(s.mesh);
    switch (kind) {
      case PlantedDefect::Fin:  // each fin becomes a triangle of its own; the sphere stays closed
        CHECK(r.components == 9);
        CHECK(s.cut_edges == 8);
        CHECK(std::abs(area(s.mesh) - area(m)) < 1e-12);
        break;
      case PlantedDefect::Bowtie:
        CHECK(s.split_vertices == 8);
        CHECK(r.components == 1);
        break;
      case PlantedDefect::ZeroArea:  // the flat triangles go, the faces across are split: closed again
        CHECK(s.split_faces == 8);
        CHECK(r.boundary_loops == 0);
        CHECK(r.genus == 0);
        CHECK(std::abs(area(s.mesh) - clean_area) < 1e-12);
        break;
      case PlantedDefect::FlippedPatch:
        CHECK(s.flipped_faces > 0);
        CHECK(r.genus == 0);
        CHECK(r.boundary_loops == 0);
        break;
      case PlantedDefect::Unreferenced:
        CHECK(s.unreferenced_vertices == 8);
        CHECK(s.mesh.num_vertices() == clean.num_vertices());
        break;
      case PlantedDefect::DuplicateFace:
        CHECK(s.dropped_faces == 8);
        CHECK(r.genus == 0);
        CHECK(std::abs(area(s.mesh) - clean_area) < 1e-12);
        break;
      case PlantedDefect::Needle:
        CHECK(r.genus == 0);
        CHECK(std::abs(area(s.mesh) - clean_area) < 1e-12);
        break;
    }
  }
}

TEST_CASE("manifold sheets: two sheets crossing on an edge, and a Moebius band") {
  // Four triangles around the edge (0, 1): two planes through it; the smooth continuations pair up.
  Mesh x;
  x.add_vertex(0, 0, 0), x.add_vertex(0, 0, 1);
  x.add_vertex(1, 0, 0.5), x.add_vertex(-1, 0, 0.5), x.add_vertex(0, 1, 0.5), x.add_vertex(0, -1, 0.5);
  x.add_triangle(0, 1, 2), x.add_triangle(1, 0, 3), x.add_triangle(0, 1, 4), x.add_triangle(1, 0, 5);
  const ManifoldSheets s = manifold_sheets(x);
  check_clean(s);
  CHECK(analyze_mesh(s.mesh).components == 2);
  // Each sheet is one plane: input faces 0 and 1 (x = +-1) share an edge, 0 and 2 share no vertex.
  auto shared = [&](int32_t a, int32_t b) {
    int32_t fa = -1, fb = -1;
    for (int32_t f = 0; f < 4; ++f) (s.face_of[f] == a ? fa : s.face_of[f] == b ? fb : f) = f;
    const int32_t va[3] = {s.mesh.f0[fa], s.mesh.f1[fa], s.mesh.f2[fa]};
    const int32_t vb[3] = {s.mesh.f0[fb], s.mesh.f1[fb], s.mesh.f2[fb]};
    int n = 0;
    for (const int32_t p : va)
      for (const int32_t q : vb) n += p == q;
    return n;
  };
  CHECK(shared(0, 1) == 2);
  CHECK(shared(2, 3) == 2);
  CHECK(shared(0, 2) == 0);

  // A band of 8 triangles closed with a half twist: not orientable, so one glued edge is cut.
  Mesh mb;
  const int n = 4;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, c = std::cos(a), sn = std::sin(a), t = 0.5 * a;
    mb.add_vertex(c * (1 + 0.3 * std::cos(t)), sn * (1 + 0.3 * std::cos(t)), 0.3 * std::sin(t));
    mb.add_vertex(c * (1 - 0.3 * std::cos(t)), sn * (1 - 0.3 * std::cos(t)), -0.3 * std::sin(t));
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    const int c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;  // the twist swaps the sides
    mb.add_triangle(a, b, c), mb.add_triangle(b, d, c);
  }
  REQUIRE_FALSE(analyze_mesh(mb).manifold);
  const ManifoldSheets band = manifold_sheets(mb);
  check_clean(band);
  CHECK(band.cut_edges >= 1);
  CHECK(analyze_mesh(band.mesh).components == 1);
}
