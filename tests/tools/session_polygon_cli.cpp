// A Session on a polygon mesh gives the `locus` CLI's numbers for the same
// file and arguments, bit for bit (session.hpp "Polygon meshes"):
// whole-mesh geodesic distance and log maps on the polygon operators (default
// t 8h^2, and an explicit --t), CVT labels on the triangulation. The CLI's
// outputs are read back from binary PLY.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

TEST_CASE("session on polygons equals the CLI: geodesic, log map, cvt labels") {
  if (!have_locus()) return;
  Scratch dir("session_polygon");
  const std::string quads = dir / "quads.obj";
  locus::write_mesh(quads, locus::make_quad_torus(16, 8));  // 128 vertices, 128 quads
  const locus::Mesh m = locus::read_mesh(quads);            // what the CLI reads
  REQUIRE_FALSE(m.is_triangle_mesh());
  const locus::Session s(m);

  for (const char* t : {"", "3h2"}) {
    CAPTURE(t);
    std::vector<std::string> time;
    locus::HeatQuery q;
    if (*t) time = {"--t", t}, q.t_factor = 3.0;
    std::vector<std::string> args = {"geodesic", quads, "--source", "5", "-o", dir / "g.ply", "--json"};
    args.insert(args.end(), time.begin(), time.end());
    const Run g = run_locus(dir, args);
    REQUIRE_MESSAGE(g.status == 0, g.err);
    CHECK(g.json()["method"] == "heat-full-polygon");
    CHECK(s.geodesic_distance(5, q) == vertex_property(dir / "g.ply", "distance"));
    CHECK(locus::Session::from_file(quads).geodesic_distance(5, q) == vertex_property(dir / "g.ply", "distance"));

    args = {"logmap", quads, "--center", "5", "--fraction", "0.3", "-o", dir / "l.ply", "--json"};
    args.insert(args.end(), time.begin(), time.end());
    const Run l = run_locus(dir, args);
    REQUIRE_MESSAGE(l.status == 0, l.err);
    CHECK(l.json()["method"] == "heat-full-polygon");
    const locus::LogMapResult r = s.logmap(5, 0.3, q);
    const std::vector<double> in_patch = vertex_property(dir / "l.ply", "in_patch");
    int64_t cnt = 0;
    for (double x : in_patch) cnt += x == 1;
    CHECK(cnt == static_cast<int64_t>(r.patch.size()));
    const std::vector<double> u = vertex_property(dir / "l.ply", "u"), v = vertex_property(dir / "l.ply", "v"),
                              d = vertex_property(dir / "l.ply", "distance"), a = vertex_property(dir / "l.ply", "angle");
    for (size_t p = 0; p < r.patch.size(); ++p) {
      const int32_t i = r.patch[p];
      CHECK(in_patch[i] == 1);
      CHECK(r.u[p] == u[i]);
      CHECK(r.v[p] == v[i]);
      CHECK(r.distance[p] == d[i]);
      CHECK(r.angle[p] == a[i]);
    }
  }

  // cvt triangulates on load, as the Session does for it.
  const Run c = run_locus(dir, {"cvt", quads, "--sites", "12", "--iters", "3", "--seed", "4", "--labels",
                                dir / "c.ply", "-o", dir / "remesh.obj"});
  REQUIRE_MESSAGE(c.status == 0, c.err);
  const std::vector<double> labels = vertex_property(dir / "c.ply", "label");
  const locus::CvtResult r = s.cvt(12, 3, 4, {}, true);
  REQUIRE(labels.size() == r.label.size());
  for (size_t i = 0; i < labels.size(); ++i) CHECK(labels[i] == r.label[i]);
}
