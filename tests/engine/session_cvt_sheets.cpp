// cvt on meshes that are not a manifold (engine/src/session_cvt_sheets.cpp):
// the remesh of the manifold sheets, labels and sites mapped back to the input.
// Oracles: the remesh's topology recomputed by analyze_mesh (independent of the
// remesh's own statistics), the input's positions (every site's position
// recomputed from its input face and barycentrics), the planted defects' kinds.
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "locus/engine/cvt_request.hpp"
#include "locus/kernels/mesh/mesh_defects_plant.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/session.hpp"

using namespace locus;

TEST_CASE("cvt on planted defects: a manifold remesh, labels and sites on the input") {
  const Mesh clean = make_icosphere(3);
  for (int k = 0; k < kNumPlantedDefects; ++k) {
    const auto kind = static_cast<PlantedDefect>(k);
    if (kind == PlantedDefect::Needle) continue;  // no cut: needles stay (the robust cells take them)
    CAPTURE(planted_defect_name(kind));
    const Mesh m = plant_mesh_defect(clean, kind, 4);
    const Session s{Mesh(m)};
    REQUIRE(s.operator_report().robust);
    CvtRequest q;
    q.sites = 60;
    q.iters = 3;
    const CvtReport r = s.cvt(q);
    CHECK(r.sheets.cut);
    REQUIRE(r.complete);
    const MeshReport rr = analyze_mesh(r.remesh);
    CHECK(rr.manifold);
    CHECK(rr.degenerate_faces == 0);
    CHECK(rr.components == r.input_stats.components);
    CHECK(rr.boundary_loops == r.input_stats.boundary_loops);
    // Labels: one per input vertex, -1 exactly at the unreferenced ones.
    REQUIRE(static_cast<int32_t>(r.label.size()) == m.num_vertices());
    std::set<int32_t> referenced(m.face_vertices.begin(), m.face_vertices.end());
    const int32_t nsites = static_cast<int32_t>(r.site_face.size());
    for (int32_t v = 0; v < m.num_vertices(); ++v) {
      if (referenced.count(v)) CHECK((r.label[v] >= 0 && r.label[v] < nsites));
      else CHECK(r.label[v] == -1);
    }
    // Sites: on an input face (or vertex), at the position the report gives.
    for (int32_t i = 0; i < nsites; ++i) {
      double p[3];
      if (r.site_face[i] < 0) {
        const int32_t v = r.site_vertex[i];
        REQUIRE(referenced.count(v));
        p[0] = m.x[v], p[1] = m.y[v], p[2] = m.z[v];
      } else {
        const int32_t f = r.site_face[i];
        REQUIRE((f >= 0 && f < m.num_faces()));
        const int32_t c[3] = {m.f0[f], m.f1[f], m.f2[f]};
        p[0] = p[1] = p[2] = 0;
        for (int j = 0; j < 3; ++j) {
          const double b = r.site_bary[3 * i + j];
          CHECK(b >= -1e-12);
          p[0] += b * m.x[c[j]], p[1] += b * m.y[c[j]], p[2] += b * m.z[c[j]];
        }
      }
      for (int d = 0; d < 3; ++d) CHECK(std::abs(p[d] - r.site_xyz[3 * i + d]) < 1e-12);
    }
  }
}

TEST_CASE("cvt on a mesh with a flipped patch: the remesh is the clean sphere's topology") {
  const Mesh m = plant_mesh_defect(make_icosphere(3), PlantedDefect::FlippedPatch, 4);
  const Session s{Mesh(m)};
  CvtRequest q;
  q.sites = 80;
  const CvtReport r = s.cvt(q);
  REQUIRE(r.complete);
  const MeshReport rr = analyze_mesh(r.remesh);
  CHECK(rr.genus == 0);
  CHECK(rr.components == 1);
  CHECK(rr.boundary_loops == 0);
  CHECK(r.sheets.flipped_faces > 0);
  // The old tier (labels and the remesh as arrays) takes the same path.
  const CvtResult c = s.cvt(80, 4, 0, {}, true);
  CHECK(c.label.size() == static_cast<size_t>(m.num_vertices()));
  CHECK(c.remeshed);
}
