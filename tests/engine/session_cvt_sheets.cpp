// cvt on meshes that are not a manifold (engine/src/session_cvt_sheets.cpp):
// the remesh of the manifold sheets, labels and sites mapped back to the input.
// Oracles: the remesh's topology recomputed by analyze_mesh (independent of the
// remesh's own statistics), the input's positions (every site's position
// recomputed from its input face and barycentrics), the planted defects' kinds.
#include <doctest/doctest.h>

#include <cmath>
#include <set>

#include "locus/engine/cvt_request.hpp"
#include "locus/engine/deform_request.hpp"
#include "locus/engine/geodesic_requests.hpp"
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

TEST_CASE("log map and deform on a mesh that is not a manifold: the center's sheet, mapped back") {
  // Bowties: the sheets equal the mesh except the split vertices, so away from
  // them the sheets' log map is the clean cotan log map of the same faces.
  const Mesh m = plant_mesh_defect(make_icosphere(4), PlantedDefect::Bowtie, 2);
  const Session s{Mesh(m)};
  REQUIRE(s.operator_report().robust);
  LogmapRequest q;
  q.center = 7;
  q.fraction = 0.05;
  const LogmapReport r = s.logmap(q);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK(r.warnings.back().find("manifold sheets") != std::string::npos);
  REQUIRE(!r.patch.empty());
  CHECK(r.patch[0] == 7);
  CHECK(r.distance[0] == 0.0);
  std::set<int32_t> unique(r.patch.begin(), r.patch.end());
  CHECK(unique.size() == r.patch.size());
  // On the unit sphere the heat distance is near the great-circle distance.
  for (size_t p = 0; p < r.patch.size(); ++p) {
    const int32_t v = r.patch[p];
    const double c = m.x[v] * m.x[7] + m.y[v] * m.y[7] + m.z[v] * m.z[7];
    CHECK(std::abs(r.distance[p] - std::acos(std::max(-1.0, std::min(1.0, c)))) < 0.02);
    CHECK(std::abs(std::hypot(r.u[p], r.v[p]) - r.distance[p]) < 1e-9);
  }
  // Deform: the handle moves by the offset, far vertices stay, every vertex is finite.
  DeformCommandRequest d;
  d.roi_seed = 7;
  d.handle = 7;
  d.offset = {0, 0, 0.05};
  const DeformCommandReport dr = s.deform(d);
  REQUIRE(dr.xyz.size() == 3 * static_cast<size_t>(m.num_vertices()));
  CHECK(std::abs(dr.xyz[3 * 7 + 2] - (m.z[7] + 0.05)) < 1e-9);
  CHECK_FALSE(dr.warnings.empty());
  int32_t far = -1;
  for (int32_t v = 0; v < m.num_vertices() && far < 0; ++v)
    if (m.x[v] * m.x[7] + m.y[v] * m.y[7] + m.z[v] * m.z[7] < -0.9) far = v;
  REQUIRE(far >= 0);
  CHECK(dr.xyz[3 * far] == m.x[far]);
  for (double x : dr.xyz) CHECK(std::isfinite(x));
}
