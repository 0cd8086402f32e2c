// The cvt command's request (engine/include/locus/engine/cvt_request.hpp):
// its defaults are the pipelines' (a public header cannot include them, so
// they are spelled twice and held equal here), its checks refuse what the
// CLI's parser refuses, with bad usage, before any work, and a polygon
// Session writes the labels on its faces as given and each site's polygon.
#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "locus/engine/cvt_request.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"
#include "locus/session.hpp"

namespace {

bool refused(const locus::CvtRequest& q) {
  try {
    locus::check_request(q);
  } catch (const locus::Error& e) {
    return e.code() == locus::ErrorCode::BadUsage;
  }
  return false;
}

}  // namespace

TEST_CASE("cvt request: the defaults are the pipelines'") {
  const locus::CvtRequest q;
  const locus::LloydOptions lo;
  const locus::RemeshOptions ro;
  CHECK(q.sites == lo.sites);
  CHECK(q.iters == lo.iterations);
  CHECK(q.stop_energy == lo.stop_energy);
  CHECK(q.anisotropy == lo.anisotropy);
  CHECK(q.seed == lo.seed);
  CHECK(q.t == std::to_string(static_cast<int>(locus::kLloydTFactor)) + "h2");
  CHECK(q.no_refine == !lo.refine);
  CHECK(q.no_split == !lo.split_faces);
  CHECK(q.fit_rings == lo.fit_rings);
  CHECK(q.fit_sigma == lo.fit_sigma);
  CHECK(q.track_quality == lo.track_quality);
  CHECK(q.repair_rounds == ro.max_repair_rounds);
  CHECK(q.refinements == ro.max_refinements);
  CHECK(q.optimize == ro.optimize_rounds);
  CHECK_NOTHROW(locus::check_request(q));
}

TEST_CASE("cvt request: bad usage before any work") {
  auto with = [](auto change) {
    locus::CvtRequest q;
    change(q);
    return refused(q);
  };
  CHECK(with([](locus::CvtRequest& q) { q.sites = 0; }));
  CHECK(with([](locus::CvtRequest& q) { q.iters = -1; }));
  CHECK(with([](locus::CvtRequest& q) { q.stop_energy = 1.5; }));
  CHECK(with([](locus::CvtRequest& q) { q.anisotropy = -0.1; }));
  CHECK(with([](locus::CvtRequest& q) { q.solver = "exact"; }));
  CHECK(with([](locus::CvtRequest& q) { q.t = "-1"; }));
  CHECK(with([](locus::CvtRequest& q) { q.centroid_t = "abc"; }));
  CHECK(with([](locus::CvtRequest& q) { q.t_centroid = "-2"; }));
  CHECK(with([](locus::CvtRequest& q) { q.t_centroid = "2", q.centroid_t = "2h2"; }));
  CHECK(with([](locus::CvtRequest& q) { q.fit_rings = 5; }));
  CHECK(with([](locus::CvtRequest& q) { q.fit_sigma = 101; }));
  CHECK(with([](locus::CvtRequest& q) { q.repair_rounds = 1001; }));
  CHECK(with([](locus::CvtRequest& q) { q.refinements = 5; }));
  CHECK(with([](locus::CvtRequest& q) { q.optimize = -1; }));
  CHECK(with([](locus::CvtRequest& q) { q.save = "a.locus", q.load = "b.locus"; }));
  CHECK(with([](locus::CvtRequest& q) { q.anisotropy = 0.05, q.save = "a.locus"; }));
  CHECK(with([](locus::CvtRequest& q) { q.labels = "labels.txt"; }));
  CHECK(with([](locus::CvtRequest& q) { q.sites_out = "/no/such/folder/sites.ply"; }));
  CHECK_FALSE(with([](locus::CvtRequest& q) { q.t_centroid = "0"; }));  // 0: the cells' time
}

TEST_CASE("cvt request: a polygon Session writes labels on its faces and each site's polygon") {
  // A 6x6-vertex quad grid: 25 quads, 50 triangles.
  locus::Mesh grid;
  const int n = 6;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.add_vertex(i, j, 0.1 * ((i * j) % 3));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int32_t v = j * n + i;
      const int32_t quad[4] = {v, v + 1, v + n + 1, v + n};
      grid.add_face(locus::ConstView<int32_t>(quad, 4));
    }
  const locus::Session s{grid};
  REQUIRE(s.has_polygons());
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "locus-cvt-request";
  std::filesystem::create_directories(dir);
  locus::CvtRequest q;
  q.sites = 6;
  q.iters = 2;
  q.labels = (dir / "labels.ply").string();
  q.sites_out = (dir / "sites.ply").string();
  const locus::CvtReport r = s.cvt(q);
  locus::MeshAttributes a;
  const locus::Mesh labelled = locus::read_mesh(q.labels, {}, &a);
  CHECK(labelled.num_faces() == 25);  // the faces as given
  bool has_label = false;
  for (const auto& p : a.vertex)
    if (p.name == "label") {
      has_label = true;
      CHECK(p.values == std::vector<double>(r.label.begin(), r.label.end()));
    }
  CHECK(has_label);
  locus::MeshAttributes sa;
  const locus::Mesh sites = locus::read_mesh(q.sites_out, {}, &sa);
  CHECK(sites.num_vertices() == static_cast<int32_t>(r.site_face.size()));
  const std::vector<int32_t> polygon_of = s.triangle_polygon();
  for (const auto& p : sa.vertex)
    if (p.name == "polygon")
      for (size_t k = 0; k < p.values.size(); ++k)
        CHECK(p.values[k] == (r.site_face[k] < 0 ? -1 : polygon_of[r.site_face[k]]));
  std::filesystem::remove_all(dir);
}
