// Tests for cvt_remesh's last-resort repair on graph-geodesic labels and its
// density passes (pipelines/include/locus/pipelines/voronoi/cvt_remesh.hpp;
// thesis §3.7.1). Oracles: the input's topology (Euler characteristic,
// components, boundary loops of kernels/mesh analyze_mesh), counted vertices
// against the request, and the site bookkeeping (sites = requested + added).
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh_io.hpp"

using namespace locus;

namespace {

void check_topology(const Mesh& input, const Mesh& remesh) {
  const MeshReport in = analyze_mesh(input), out = analyze_mesh(remesh);
  CHECK(out.manifold);
  CHECK(out.non_manifold_edges == 0);
  CHECK(out.unreferenced_vertices == 0);
  CHECK(out.components == in.components);
  CHECK(out.boundary_loops == in.boundary_loops);
  CHECK(out.euler_characteristic == in.euler_characteristic);
}

void check_counts(const RemeshResult& r, int32_t sites) {
  CHECK(r.requested == sites);
  CHECK(r.delivered == r.remesh.num_vertices());
  CHECK(static_cast<int32_t>(r.lloyd.sites.size()) == sites + r.added_sites);
  CHECK(r.added_sites == r.repair_sites - r.removed_sites);
}

// A sample mesh remeshed with 1,000 sites, its topology checked against the
// input's; nothing when the mesh is not fetched.
std::optional<RemeshResult> sample_remesh_1000(const std::string& path) {
  if (!std::filesystem::exists(path)) {
    MESSAGE(path << " not present (run tools/fetch_meshes.sh); skipping");
    return std::nullopt;
  }
  const Mesh m = read_mesh(path);
  RemeshOptions o;
  o.lloyd.sites = 1000;
  const MeshDerived d = derive_mesh(m);
  RemeshResult r = cvt_remesh(m, d, o, RunContext{});
  REQUIRE(r.complete);
  check_topology(m, r.remesh);
  return r;
}

// A tube of one ring of needles: 2 nu triangles of height `height`, width
// 2 pi / nu (angles of ~2.8 degrees for nu = 64, height 2), the fan strips a
// CAD tessellation gives a cylinder.
Mesh needle_tube(int32_t nu, double height) {
  Mesh m;
  for (int32_t j = 0; j <= 1; ++j)
    for (int32_t i = 0; i < nu; ++i) {
      const double a = 2 * M_PI * i / nu;
      m.add_vertex(std::cos(a), std::sin(a), height * j);
    }
  for (int32_t i = 0; i < nu; ++i) {
    const int32_t a = i, b = (i + 1) % nu, c = nu + i, d = nu + (i + 1) % nu;
    m.add_triangle(a, b, c);
    m.add_triangle(b, d, c);
  }
  return m;
}

}  // namespace

TEST_CASE("cvt remesh: without heat repair, the graph-geodesic rounds still give the input's topology") {
  // No heat rounds and no finer levels: whatever the first partition breaks,
  // only the geodesic rounds can mend it.
  // A torus with 8 sites: cells wrap the handle, one heat round cannot mend
  // them (the geodesic rounds must run); needle strips.
  struct Case {
    Mesh m;
    int32_t sites;
    bool geodesic;
  };
  const Case cases[] = {{make_torus(48, 16), 8, true}, {needle_tube(64, 2.0), 12, false}, {needle_tube(64, 2.0), 60, false}};
  for (const Case& c : cases) {
    CAPTURE(c.m.num_vertices());
    RemeshOptions o;
    o.lloyd.sites = c.sites;
    o.lloyd.iterations = 4;
    o.max_repair_rounds = 1;
    o.max_refinements = 0;
    const MeshDerived d = derive_mesh(c.m);
    const RemeshResult r = cvt_remesh(c.m, d, o, RunContext{});
    REQUIRE(r.complete);
    if (c.geodesic) CHECK(r.geodesic_rounds > 0);
    check_topology(c.m, r.remesh);
    check_counts(r, c.sites);
  }
  SUBCASE("no repair at all (max_repair_rounds = 0): a torus with 3 sites stays incomplete") {
    RemeshOptions o;
    o.lloyd.sites = 3;
    o.lloyd.iterations = 2;
    o.max_repair_rounds = 0;
    const Mesh m = make_torus(24, 8);
    const MeshDerived d = derive_mesh(m);
    const RemeshResult r = cvt_remesh(m, d, o, RunContext{});
    CHECK_FALSE(r.complete);
    CHECK(r.geodesic_rounds == 0);
    CHECK(r.remesh.num_faces() == 0);
  }
}

TEST_CASE("cvt remesh: CAD needles (ALSTOM_TEST4: 6 components, 6 loops) at 1,000 sites: topology and density") {
  const std::optional<RemeshResult> r = sample_remesh_1000(LOCUS_MESH_CACHE_DIR "/ALSTOM_TEST4.off");
  if (!r) return;
  check_counts(*r, 1000);
  CHECK(std::abs(r->delivered - 1000) <= 20);
}

// 106 holes on 2,798 vertices: the repair's sites around the holes leave the
// dual above the request after the density passes; the edge collapses
// (remesh_collapse.hpp) bring it to the request, the topology kept.
TEST_CASE("cvt remesh: elephant-with-holes at 1,000 sites: the requested count within 2%, topology kept") {
  const std::optional<RemeshResult> r = sample_remesh_1000(LOCUS_MESH_CACHE_DIR "/elephant-with-holes.off");
  if (!r) return;
  CHECK(r->delivered == r->remesh.num_vertices());
  CHECK(std::abs(r->delivered - 1000) <= 20);
}

TEST_CASE("cvt remesh: the density passes bring a torus with thin handles to the requested count") {
  // A thin torus (tube radius a tenth of the ring's): the repair adds sites
  // around the tube, the passes drop as many elsewhere.
  const Mesh m = make_torus(160, 16, 1.0, 0.1);
  for (int passes : {0, 4}) {
    CAPTURE(passes);
    RemeshOptions o;
    o.lloyd.sites = 200;
    o.lloyd.iterations = 6;
    o.density_passes = passes;
    const MeshDerived d = derive_mesh(m);
    const RemeshResult r = cvt_remesh(m, d, o, RunContext{});
    REQUIRE(r.complete);
    check_topology(m, r.remesh);
    check_counts(r, 200);
    if (passes == 0) CHECK(r.density_passes == 0);
    if (passes > 0) CHECK(std::abs(r.delivered - 200) <= 4);
  }
}
