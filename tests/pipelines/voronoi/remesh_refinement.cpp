// Tests for pipelines/voronoi remesh_refinement and the remesh's fallback to a
// subdivided input (cvt_remesh.hpp, thesis §3.7.1). Oracles: positions of the
// same point computed on the coarse and the fine mesh (midpoint subdivision
// keeps the surface); topology counted directly from the output's faces
// (vertices - edges + faces, components, boundary edges), not by the library.
#include "locus/pipelines/voronoi/remesh_refinement.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

using namespace locus;

namespace {

double dist(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Counted from the faces alone: Euler characteristic, components, edges in one
// face, edges in more than two faces.
struct Counts {
  int64_t chi = 0, components = 0, boundary_edges = 0, bad_edges = 0;
};
Counts count(const Mesh& m) {
  std::map<std::pair<int32_t, int32_t>, int> edges;
  std::vector<int32_t> parent(m.num_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::set<int32_t> used;
  for (int32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = m.face(f)[k], b = m.face(f)[(k + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
      parent[find(a)] = find(b);
      used.insert(a);
    }
  Counts c;
  c.chi = static_cast<int64_t>(used.size()) - static_cast<int64_t>(edges.size()) + m.num_faces();
  for (int32_t v : used) c.components += find(v) == v;
  for (const auto& [e, k] : edges) {
    c.boundary_edges += k == 1;
    c.bad_edges += k > 2;
  }
  return c;
}

}  // namespace

TEST_CASE("remesh refinement: points keep their position on the subdivided mesh and back") {
  const Mesh m = make_torus(9, 5);
  const Mesh fine = subdivide_midpoint(m, 1);
  std::vector<SurfacePoint> p = random_surface_points(m, 200, 7);
  p.push_back(vertex_point(3));
  p.push_back(SurfacePoint{4, -1, {0.5, 0.5, 0.0}});  // an edge midpoint: a vertex of the fine mesh
  p.push_back(SurfacePoint{5, -1, {1.0 / 3, 1.0 / 3, 1.0 / 3}});
  const std::vector<SurfacePoint> q = refine_surface_points(m, p);
  REQUIRE(q.size() == p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    CAPTURE(i);
    check_surface_point(fine, q[i], "refined", i);
    CHECK(dist(surface_point_position(m, p[i]), surface_point_position(fine, q[i])) < 1e-12);
    if (p[i].face >= 0) CHECK(q[i].face / 4 == p[i].face);  // a child of its face
  }
  // Back, also from the fine mesh's own vertices (midpoints: ids beyond m's).
  std::vector<SurfacePoint> f = q;
  for (int32_t v = m.num_vertices(); v < m.num_vertices() + 20; ++v) f.push_back(vertex_point(v));
  const std::vector<SurfacePoint> back = coarsen_surface_points(m, fine, f);
  for (size_t i = 0; i < f.size(); ++i) {
    CAPTURE(i);
    check_surface_point(m, back[i], "coarsened", i);
    CHECK(dist(surface_point_position(fine, f[i]), surface_point_position(m, back[i])) < 1e-12);
  }
}

TEST_CASE("cvt remesh: nearly as many sites as vertices (the input is subdivided): topology and density kept") {
  struct Case {
    Mesh m;
    int32_t sites;
    int64_t chi;
  };
  const Case cases[] = {{make_icosphere(2), 150, 2}, {make_torus(16, 8), 120, 0}};
  for (const Case& c : cases) {
    CAPTURE(c.m.num_vertices());
    RemeshOptions o;
    o.lloyd.sites = c.sites;
    o.lloyd.iterations = 6;
    const MeshDerived d = derive_mesh(c.m);
    const RemeshResult r = cvt_remesh(c.m, d, o, RunContext{});
    REQUIRE(r.complete);
    CHECK(r.refinements >= 1);
    const Counts k = count(r.remesh);
    CHECK(k.chi == c.chi);
    CHECK(k.components == 1);
    CHECK(k.boundary_edges == 0);
    CHECK(k.bad_edges == 0);
    // Cells resolved below the input's spacing, the density passes: the
    // requested count within 2%.
    CHECK(std::abs(r.remesh.num_vertices() - c.sites) <= c.sites / 50);
    CHECK(r.delivered == r.remesh.num_vertices());
    CHECK(r.requested == c.sites);
    // Labels and sites are reported on the input.
    CHECK(r.lloyd.label.size() == static_cast<size_t>(c.m.num_vertices()));
    for (size_t i = 0; i < r.lloyd.sites.size(); ++i) check_surface_point(c.m, r.lloyd.sites[i], "site", i);
    // Every remesh vertex lies on the input's surface: at a site's position.
    for (int32_t v = 0; v < r.remesh.num_vertices(); ++v) CHECK(r.vertex_site[v] < static_cast<int32_t>(r.lloyd.sites.size()));
  }
}
