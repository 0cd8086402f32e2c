// Tests for the C API of the diffusion, shape and Voronoi pipelines (engine/include/locus/locus.h,
// the section after locus_heat_values): each call returns what the C++ Session
// returns for the same arguments (the Session is checked against oracles in
// tests/engine/session_*.cpp), outputs land where locus.h says, and every bad
// argument is a status code naming it: ids out of range (vertices, faces) are
// LOCUS_BAD_USAGE (2), as locus.h promises.
#include "locus/locus.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/session.hpp"

using namespace locus;

namespace {

bool message_has(const char* what) { return std::string(locus_last_error_message()).find(what) != std::string::npos; }

// A C session and the C++ Session of the same mesh.
struct Both {
  Mesh mesh;
  Session cpp;
  locus_session* c = nullptr;
  explicit Both(Mesh m) : mesh(m), cpp(m) {
    std::vector<double> xyz;
    for (int32_t i = 0; i < m.num_vertices(); ++i) xyz.insert(xyz.end(), {m.x[i], m.y[i], m.z[i]});
    REQUIRE(locus_session_create(xyz.data(), m.num_vertices(), m.face_vertices.data(), m.num_faces(), &c) == LOCUS_OK);
  }
  ~Both() { locus_session_destroy(c); }
  int64_t nv() const { return mesh.num_vertices(); }
};

locus_surface_point at_vertex(int64_t v) { return locus_surface_point{-1, v, {1, 0, 0}}; }
locus_surface_point in_face(int64_t f, double a, double b, double c) { return locus_surface_point{f, -1, {a, b, c}}; }

}  // namespace

TEST_CASE("C API multi-source geodesic: the Session's distances; bad points are LOCUS_BAD_USAGE") {
  Both b(make_icosphere(3));
  const locus_surface_point src[3] = {at_vertex(0), at_vertex(50), in_face(20, 0.1, 0.2, 0.7)};
  std::vector<double> d(b.nv());
  REQUIRE(locus_geodesic_distance_multi(b.c, src, 3, d.data(), nullptr) == LOCUS_OK);
  const std::vector<MeshPoint> pts{MeshPoint::at_vertex(0), MeshPoint::at_vertex(50), MeshPoint::in_face(20, 0.1, 0.2, 0.7)};
  CHECK(d == b.cpp.geodesic_distance(pts));
  locus_run_options o = locus_run_options_default();
  o.t_factor = 2.0;
  REQUIRE(locus_geodesic_distance_multi(b.c, src, 3, d.data(), &o) == LOCUS_OK);
  CHECK(d == b.cpp.geodesic_distance(pts, HeatQuery{2.0}));

  const locus_surface_point bad_face[1] = {in_face(b.mesh.num_faces(), 1, 0, 0)};
  CHECK(locus_geodesic_distance_multi(b.c, bad_face, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("sources[0].face"));
  const locus_surface_point bad_vertex[2] = {at_vertex(0), at_vertex(b.nv())};
  CHECK(locus_geodesic_distance_multi(b.c, bad_vertex, 2, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("sources[1].vertex"));
  const locus_surface_point bad_bary[1] = {in_face(0, 0.5, 0.5, 0.5)};
  CHECK(locus_geodesic_distance_multi(b.c, bad_bary, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, src, 0, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, nullptr, 1, d.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(b.c, src, 3, nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_geodesic_distance_multi(nullptr, src, 3, d.data(), nullptr) == LOCUS_BAD_USAGE);
}

TEST_CASE("C API Voronoi: labels, points and polylines of the Session; capacities are checked") {
  Both b(make_icosphere(3));
  const locus_surface_point g[4] = {at_vertex(0), at_vertex(200), at_vertex(500), in_face(700, 0.2, 0.2, 0.6)};
  const std::vector<MeshPoint> pts{MeshPoint::at_vertex(0), MeshPoint::at_vertex(200), MeshPoint::at_vertex(500),
                                   MeshPoint::in_face(700, 0.2, 0.2, 0.6)};
  const VoronoiResult r = b.cpp.voronoi(pts);
  int64_t max_points = 0, max_lines = 0, max_line_points = 0;
  REQUIRE(locus_voronoi_bound(b.c, &max_points, &max_lines, &max_line_points) == LOCUS_OK);
  std::vector<int32_t> labels(b.nv());
  std::vector<double> points(3 * max_points);
  std::vector<int64_t> offsets(max_lines + 1), line_points(max_line_points);
  locus_voronoi_output out{labels.data(), points.data(), max_points, 0, offsets.data(), max_lines, 0,
                           line_points.data(), max_line_points, 0};
  REQUIRE(locus_voronoi(b.c, g, 4, &out, nullptr) == LOCUS_OK);
  CHECK(labels == r.label);
  REQUIRE(out.n_points == static_cast<int64_t>(r.points.size() / 3));
  CHECK(std::vector<double>(points.begin(), points.begin() + 3 * out.n_points) == r.points);
  REQUIRE(out.n_lines + 1 == static_cast<int64_t>(r.line_offsets.size()));
  REQUIRE(out.n_line_points == static_cast<int64_t>(r.line_points.size()));
  for (int64_t k = 0; k <= out.n_lines; ++k) CHECK(offsets[k] == r.line_offsets[k]);
  for (int64_t k = 0; k < out.n_line_points; ++k) CHECK(line_points[k] == r.line_points[k]);
  CHECK(out.n_points <= max_points);

  // Too small a capacity: the counts come back with LOCUS_BAD_USAGE naming it.
  locus_voronoi_output small{nullptr, points.data(), 1, 0, nullptr, 0, 0, nullptr, 0, 0};
  CHECK(locus_voronoi(b.c, g, 4, &small, nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("points_capacity"));
  CHECK(small.n_points == out.n_points);
  const locus_surface_point bad[1] = {at_vertex(-5)};
  CHECK(locus_voronoi(b.c, bad, 1, &out, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_voronoi(b.c, g, 4, nullptr, nullptr) == LOCUS_BAD_USAGE);
}

TEST_CASE("C API natural neighbors (prepared and one-shot) and skinning weights: the Session's numbers") {
  Both b(make_icosphere(3));
  const locus_surface_point sites[4] = {at_vertex(0), at_vertex(100), at_vertex(400), at_vertex(600)};
  const std::vector<MeshPoint> ps{MeshPoint::at_vertex(0), MeshPoint::at_vertex(100), MeshPoint::at_vertex(400),
                                  MeshPoint::at_vertex(600)};
  locus_nncoords_field* nn = nullptr;
  REQUIRE(locus_nncoords_prepare(b.c, sites, 4, nullptr, &nn) == LOCUS_OK);
  CHECK(locus_nncoords_site_count(nn) == 4);
  const NaturalNeighbors F = b.cpp.prepare_natural_neighbors(ps);
  double w[4];
  for (int64_t f = 0; f < b.mesh.num_faces(); f += 131) {
    const locus_surface_point q = in_face(f, 0.6, 0.2, 0.2);
    REQUIRE(locus_nncoords_query(nn, &q, w) == LOCUS_OK);
    CHECK(std::vector<double>(w, w + 4) == F.coordinates(MeshPoint::in_face(static_cast<int32_t>(f), 0.6, 0.2, 0.2)).weight);
  }
  const locus_surface_point bad = in_face(b.mesh.num_faces(), 1, 0, 0);
  CHECK(locus_nncoords_query(nn, &bad, w) == LOCUS_BAD_USAGE);
  CHECK(message_has("point.face"));
  // The field outlives the session it came from.
  const locus_surface_point q = in_face(10, 0.3, 0.3, 0.4);
  double before[4], after[4];
  REQUIRE(locus_nncoords_query(nn, &q, before) == LOCUS_OK);
  REQUIRE(locus_nncoords(b.c, sites, 4, &q, after, nullptr) == LOCUS_OK);
  CHECK(std::vector<double>(before, before + 4) == std::vector<double>(after, after + 4));
  locus_session_destroy(b.c);
  b.c = nullptr;
  REQUIRE(locus_nncoords_query(nn, &q, after) == LOCUS_OK);
  CHECK(std::vector<double>(before, before + 4) == std::vector<double>(after, after + 4));
  locus_nncoords_destroy(nn);
  CHECK(locus_nncoords_site_count(nullptr) == -1);

  Both c(make_icosphere(2));
  const locus_surface_point handles[2] = {at_vertex(0), at_vertex(100)};
  std::vector<double> sw(2 * c.nv());
  REQUIRE(locus_skinning_weights(c.c, handles, 2, sw.data(), nullptr) == LOCUS_OK);
  CHECK(sw == c.cpp.skinning_weights(std::vector<MeshPoint>{MeshPoint::at_vertex(0), MeshPoint::at_vertex(100)}).weight);
  CHECK(locus_skinning_weights(c.c, handles, 0, sw.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_nncoords(c.c, handles, 2, &bad, w, nullptr) == LOCUS_BAD_USAGE);

  // The skinweights command: a vertex-set handle {0, 1} and a vertex handle
  // 100 (a small mesh: exact rows everywhere); the Session's weights bit for bit, rows summing to 1.
  locus_skinweights_options so = locus_skinweights_options_default();
  const int64_t ids[3] = {0, 1, 100}, offsets[3] = {0, 2, 3};
  so.handles = ids;
  so.handle_offsets = offsets;
  so.n_handles = 2;
  locus_skinweights_report sr;
  REQUIRE(locus_skinweights_run(c.c, &so, sw.data(), &sr, nullptr) == LOCUS_OK);
  SkinningRequest sq;
  sq.handles = {{0, 1}, {100}};
  const SkinningReport want = c.cpp.skinning(sq);
  CHECK(sw == want.weight);
  CHECK(sr.handles == 2);
  CHECK(sr.samples == want.samples);
  for (int32_t v = 0; v < c.nv(); ++v) CHECK(sw[2 * v] + sw[2 * v + 1] == doctest::Approx(1.0).epsilon(1e-12));
  so.samples = -1;
  CHECK(locus_skinweights_run(c.c, &so, sw.data(), &sr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_skinweights_run(c.c, nullptr, sw.data(), &sr, nullptr) == LOCUS_BAD_USAGE);
}

TEST_CASE("C API ADF, HKS and heat exchange: the Session's numbers") {
  Both b(make_icosphere(3));
  const int64_t v[3] = {0, 10, 600};
  const std::vector<int32_t> v32{0, 10, 600};
  double adf[3];
  REQUIRE(locus_adf(b.c, v, 3, 0, adf, nullptr) == LOCUS_OK);
  CHECK(std::vector<double>(adf, adf + 3) == b.cpp.auto_diffusion(v32));
  std::vector<double> all(b.nv());
  REQUIRE(locus_adf(b.c, nullptr, 0, 1, all.data(), nullptr) == LOCUS_OK);
  CHECK(all == b.cpp.auto_diffusion({}, {}, DiagonalMethod::SelectedInversion));
  const double ts[2] = {1.0, 10.0};
  double hks[6];
  REQUIRE(locus_hks(b.c, ts, 2, v, 3, 0, hks, nullptr) == LOCUS_OK);
  const std::vector<HeatQuery> tq{HeatQuery{1.0, 0.0}, HeatQuery{10.0, 0.0}};
  CHECK(std::vector<double>(hks, hks + 6) == b.cpp.heat_kernel_signature(tq, v32));
  const int64_t src[2] = {1, 2}, tgt[2] = {300, 1};
  double hx[2];
  locus_run_options o = locus_run_options_default();
  o.t_factor = 4;
  REQUIRE(locus_heat_exchange(b.c, src, 2, tgt, 2, hx, &o) == LOCUS_OK);
  CHECK(std::vector<double>(hx, hx + 2) == b.cpp.heat_exchange(std::vector<int32_t>{1, 2}, std::vector<int32_t>{300, 1}, HeatQuery{4.0, 0.0}));

  const int64_t bad[1] = {b.nv()};
  CHECK(locus_adf(b.c, bad, 1, 0, adf, nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("vertices[0]"));
  CHECK(locus_adf(b.c, nullptr, 3, 0, adf, nullptr) == LOCUS_BAD_USAGE);
  const double bad_t[1] = {-1};
  CHECK(locus_hks(b.c, bad_t, 1, v, 3, 0, hks, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_heat_exchange(b.c, src, 2, bad, 1, hx, nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("targets[0]"));
}

TEST_CASE("C API deformation and parameterizations: the Session's numbers") {
  Both b(make_icosphere(3));
  locus_deform_request req{5, 0.2, 5, 1, 0, {0.01, 0.02, -0.03}};
  std::vector<double> xyz(3 * b.nv());
  REQUIRE(locus_deform(b.c, &req, xyz.data(), nullptr) == LOCUS_OK);
  DeformRequest r;
  r.roi_seed = 5;
  r.roi_fraction = 0.2;
  r.handle_vertex = 5;
  r.offset = {0.01, 0.02, -0.03};
  CHECK(xyz == b.cpp.deform(r).xyz);
  req.bilaplacian = 1;
  REQUIRE(locus_deform(b.c, &req, xyz.data(), nullptr) == LOCUS_OK);
  r.energy = DeformEnergyKind::Bilaplacian;
  CHECK(xyz == b.cpp.deform(r).xyz);
  req.handle_vertex = b.nv();
  CHECK(locus_deform(b.c, &req, xyz.data(), nullptr) == LOCUS_BAD_USAGE);
  CHECK(message_has("handle_vertex"));

  std::vector<double> uv(2 * b.nv());
  int64_t size = 0, flipped = -1;
  REQUIRE(locus_param_patch(b.c, 7, 0.1, 1, uv.data(), &size, &flipped, nullptr) == LOCUS_OK);
  const PatchParamResult p = b.cpp.parameterize_patch({7, 0.1, PatchBoundary::Circle});
  CHECK(size == static_cast<int64_t>(p.vertices.size()));
  CHECK(flipped == p.flipped_faces);
  int64_t inside = 0;
  for (int64_t i = 0; i < b.nv(); ++i) inside += !std::isnan(uv[2 * i]);
  CHECK(inside == size);
  for (size_t k = 0; k < p.vertices.size(); ++k) CHECK(uv[2 * p.vertices[k]] == p.uv[2 * k]);
  CHECK(locus_param_patch(b.c, 7, 0.1, 2, uv.data(), &size, &flipped, nullptr) == LOCUS_BAD_USAGE);

  Mesh disk = make_disk(4);
  for (int32_t i = 0; i < disk.num_vertices(); ++i) disk.z[i] = 0.3 * disk.x[i] * disk.y[i];
  Both d(disk);
  std::vector<double> duv(2 * d.nv());
  REQUIRE(locus_param_disk(d.c, 0, 100, 1e-6, duv.data(), &flipped, nullptr) == LOCUS_OK);
  CHECK(duv == d.cpp.parameterize_disk({DiskParamMethod::Perfect, 100, 1e-6}).uv);
  CHECK(flipped == 0);
  CHECK(locus_param_disk(b.c, 0, 100, 1e-6, uv.data(), nullptr, nullptr) == LOCUS_BAD_INPUT);  // a closed mesh
  CHECK(locus_param_disk(d.c, 3, 100, 1e-6, duv.data(), nullptr, nullptr) == LOCUS_BAD_USAGE);

  const int64_t ne = locus_session_edge_count(d.c);
  CHECK(ne == d.cpp.num_edges());
  std::vector<int32_t> edges(2 * ne);
  std::vector<double> w(ne), pos(3 * d.nv());
  int32_t converged = -1;
  REQUIRE(locus_perfect_laplacian(d.c, 0, 100, 1e-6, edges.data(), w.data(), pos.data(), &converged, nullptr) == LOCUS_OK);
  const PerfectLaplacianOutput pl = d.cpp.perfect_laplacian({false, 100, 1e-6, true});
  CHECK(edges == pl.edges);
  CHECK(w == pl.weights);
  CHECK(pos == pl.xyz);
  CHECK(converged == (pl.converged ? 1 : 0));
  REQUIRE(locus_self_supporting(d.c, 2.0, 50, 1e-6, edges.data(), w.data(), pos.data(), &converged, nullptr) == LOCUS_OK);
  const SelfSupportOutput ss = d.cpp.self_supporting({2.0, 50, 1e-6});
  CHECK(w == ss.forces);
  CHECK(pos == ss.xyz);
  CHECK(locus_self_supporting(d.c, -1.0, 50, 1e-6, nullptr, nullptr, nullptr, nullptr, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_session_edge_count(nullptr) == -1);
}

TEST_CASE("C API prepare: the operators are built once, eagerly; later queries factor nothing") {
  Both b(make_icosphere(2));
  REQUIRE(locus_session_prepare(b.c, LOCUS_PREPARE_HEAT_METHOD | LOCUS_PREPARE_DIFFUSION | LOCUS_PREPARE_LAPLACIAN,
                                nullptr) == LOCUS_OK);
  const int64_t v[2] = {0, 5};
  double adf[2];
  std::vector<double> uv(2 * b.nv()), d(b.nv());
  const locus_surface_point src[1] = {at_vertex(3)};
  // The same queries on the C++ Session after its prepare calls build nothing more.
  b.cpp.prepare_heat();
  b.cpp.prepare_diffusion();
  b.cpp.prepare_patch_parameterization();
  const locus::SessionStats before = b.cpp.stats();
  CHECK(before.numeric_factorizations == 2);
  CHECK(before.heat_engines == 1);
  REQUIRE(locus_adf(b.c, v, 2, 0, adf, nullptr) == LOCUS_OK);
  REQUIRE(locus_param_patch(b.c, 0, 0.2, 0, uv.data(), nullptr, nullptr, nullptr) == LOCUS_OK);
  REQUIRE(locus_geodesic_distance_multi(b.c, src, 1, d.data(), nullptr) == LOCUS_OK);
  CHECK(std::vector<double>(adf, adf + 2) == b.cpp.auto_diffusion(std::vector<int32_t>{0, 5}));
  b.cpp.parameterize_patch({0, 0.2, PatchBoundary::Neumann});
  b.cpp.geodesic_distance(3);
  CHECK(b.cpp.stats().numeric_factorizations == before.numeric_factorizations);
  CHECK(b.cpp.stats().heat_engines == before.heat_engines);
  CHECK(locus_session_prepare(b.c, 8, nullptr) == LOCUS_BAD_USAGE);
  CHECK(locus_session_prepare(nullptr, 1, nullptr) == LOCUS_BAD_USAGE);
}

TEST_CASE("C API random surface points: the Session's, in faces with valid weights") {
  Both b(make_icosphere(2));
  std::vector<locus_surface_point> p(40);
  REQUIRE(locus_random_surface_points(b.c, 40, 3, p.data()) == LOCUS_OK);
  const std::vector<MeshPoint> q = b.cpp.random_points(40, 3);
  REQUIRE(q.size() == 40);
  for (size_t k = 0; k < q.size(); ++k) {
    CHECK(p[k].face == q[k].face);
    CHECK(p[k].face >= 0);
    CHECK(p[k].face < b.mesh.num_faces());
    CHECK(p[k].bary[0] == q[k].bary[0]);
    CHECK(p[k].bary[1] == q[k].bary[1]);
    CHECK(p[k].bary[0] + p[k].bary[1] + p[k].bary[2] == doctest::Approx(1.0));
    CHECK(std::min({p[k].bary[0], p[k].bary[1], p[k].bary[2]}) >= 0.0);
  }
  const MeshPoint other = b.cpp.random_points(40, 4)[0];  // another seed, another stream
  CHECK((other.face != q[0].face || other.bary != q[0].bary));
  CHECK(locus_random_surface_points(b.c, -1, 3, p.data()) == LOCUS_BAD_USAGE);
  CHECK(locus_random_surface_points(b.c, 1, 3, nullptr) == LOCUS_BAD_USAGE);
}

namespace {
int stop_at_first(double, const char*, void* user) {
  ++*static_cast<int*>(user);
  return 1;
}
}  // namespace

TEST_CASE("C API pipelines: a progress callback that asks to stop cancels; the session answers afterwards") {
  Both b(make_icosphere(3));
  int calls = 0;
  locus_run_options o = locus_run_options_default();
  o.progress = stop_at_first;
  o.user_data = &calls;
  const locus_surface_point g[3] = {at_vertex(0), at_vertex(100), at_vertex(300)};
  locus_voronoi_output out{};
  std::vector<int32_t> labels(b.nv());
  out.labels = labels.data();
  CHECK(locus_voronoi(b.c, g, 3, &out, &o) == LOCUS_CANCELLED);
  CHECK(calls >= 1);
  std::vector<double> d(b.nv());
  CHECK(locus_geodesic_distance_multi(b.c, g, 3, d.data(), &o) == LOCUS_CANCELLED);
  const int64_t v[1] = {5};
  double adf = 0;
  CHECK(locus_adf(b.c, v, 1, 0, &adf, &o) == LOCUS_CANCELLED);
  // Nothing cancelled was cached: the same calls without the callback give the Session's answers.
  REQUIRE(locus_voronoi(b.c, g, 3, &out, nullptr) == LOCUS_OK);
  CHECK(labels == b.cpp.voronoi(std::vector<MeshPoint>{MeshPoint::at_vertex(0), MeshPoint::at_vertex(100),
                                                       MeshPoint::at_vertex(300)}).label);
  REQUIRE(locus_geodesic_distance_multi(b.c, g, 3, d.data(), nullptr) == LOCUS_OK);
  REQUIRE(locus_adf(b.c, v, 1, 0, &adf, nullptr) == LOCUS_OK);
  CHECK(adf == b.cpp.auto_diffusion(std::vector<int32_t>{5})[0]);
}

TEST_CASE("C API commands whose options give their time refuse opts->t_factor, before any work") {
  // Before the run frame checked it, skinweights, perfect-laplacian and
  // selfsupport silently ignored opts->t_factor.
  Both c(make_icosphere(2));
  locus_run_options ro = locus_run_options_default();
  ro.t_factor = 2.0;
  locus_skinweights_options so = locus_skinweights_options_default();
  const int64_t ids[2] = {0, 100};
  so.handles = ids;
  so.n_handles = 2;
  std::vector<double> sw(2 * c.nv());
  CHECK(locus_skinweights_run(c.c, &so, sw.data(), nullptr, &ro) == LOCUS_BAD_USAGE);
  CHECK(message_has("opts->t_factor must be 0"));
  const locus_perfect_laplacian_options po = locus_perfect_laplacian_options_default();
  CHECK(locus_perfect_laplacian_run(c.c, &po, nullptr, nullptr, nullptr, nullptr, &ro) == LOCUS_BAD_USAGE);
  CHECK(message_has("opts->t_factor must be 0"));
  const locus_selfsupport_options ss = locus_selfsupport_options_default();
  CHECK(locus_selfsupport_run(c.c, &ss, nullptr, nullptr, nullptr, nullptr, &ro) == LOCUS_BAD_USAGE);
  CHECK(message_has("opts->t_factor must be 0"));
  locus_deform_options dopt = locus_deform_options_default();
  std::vector<double> xyz(3 * c.nv());
  CHECK(locus_deform_run(c.c, &dopt, xyz.data(), nullptr, &ro) == LOCUS_BAD_USAGE);
  CHECK(message_has("opts->t_factor must be 0"));
  // Without it, the same skinning call answers.
  CHECK(locus_skinweights_run(c.c, &so, sw.data(), nullptr, nullptr) == LOCUS_OK);
}
