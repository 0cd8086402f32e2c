// locus::Session on polygon meshes (session.hpp "Polygon
// meshes"): the heat method on the polygon operators (thesis §6.4-6.6 on the
// virtual-vertex operators of pipelines/.../geodesic/polygon_heat_geodesic.hpp),
// the same computation as `locus geodesic` / `locus logmap` on a polygon file,
// so the numbers are the CLI's bit for bit; and the triangulation every other
// pipeline runs on.
#include <cmath>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {

Mesh triangulate_for_session(const Mesh& polygons, std::vector<int32_t>& face_of) {
  validate_mesh_arrays(polygons);  // ids in range before the triangulation reads positions
  TriangulatedMesh t = triangulate_polygons(polygons, mesh_name(polygons));
  face_of = std::move(t.face_of);
  return std::move(t.mesh);
}

std::shared_ptr<const Mesh> polygons_moved(const Mesh& polygons, const Mesh& moved) {
  auto p = std::make_shared<Mesh>(polygons);
  p->x = moved.x;
  p->y = moved.y;
  p->z = moved.z;
  // The triangulation stays (same connectivity), but the polygons must still be
  // simple: the check names the face that is not (as on construction).
  (void)triangulate_polygons(*p, mesh_name(*p));
  return p;
}

double polygon_t_factor(const HeatQuery& q) {
  return q.t_factor == 0.0 ? PolygonHeatGeodesicOptions{}.t_factor : q.t_factor;
}

std::shared_ptr<const PolygonLogMap> polygon_engine(State& s, const HeatQuery& q, const RunContext& ctx) {
  const double tf = polygon_t_factor(q);
  check_heat_method_time(q, tf);
  return s.polygon_engines.get(bits_of(tf), ctx, [&] {
    ctx.report(0.0, "prepare polygon heat method");
    PolygonHeatGeodesicOptions o;  // the CLI's: only t_factor is set
    o.t_factor = tf;
    auto e = std::make_shared<const PolygonLogMap>(*s.polygons, o, ctx);
    s.counters->engines.fetch_add(1);
    ctx.report(1.0, "prepare polygon heat method");
    return e;
  });
}

namespace {

// +infinity / other components: NaN (no value); a NaN from the solver in a
// component with a source is an error, never an answer.
void finish_distance(const State& s, const std::vector<char>& has_source, View<double> out, double t) {
  const auto& comp = s.derived->component;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!has_source[comp[i]] || std::isinf(out[i])) {
      out[i] = std::numeric_limits<double>::quiet_NaN();
    } else if (std::isnan(out[i])) {
      fail(ErrorCode::Numerical, "geodesic_distance: the distance is NaN at vertex " + std::to_string(i) +
                                     " (t = " + std::to_string(t) + ")");
    }
  }
}

}  // namespace

void polygon_geodesic(State& s, int32_t source, View<double> out, const HeatQuery& q, const RunContext& ctx) {
  const CallProgress progress(ctx, !s.polygon_engines.contains(bits_of(polygon_t_factor(q))));
  const auto e = polygon_engine(s, q, progress.build());
  ctx.check_cancel();
  const PolygonHeatGeodesic& g = e->geodesic();
  g.query_full(source, std::span<double>(out.data(), out.size()));
  std::vector<char> has_source(static_cast<size_t>(s.derived->components), 0);
  has_source[s.derived->component[source]] = 1;
  finish_distance(s, has_source, out, g.time());
  progress.finish("geodesic distance");
}

void polygon_geodesic(State& s, std::span<const SurfacePoint> sources, View<double> out, const HeatQuery& q,
                      const RunContext& ctx) {
  const CallProgress progress(ctx, !s.polygon_engines.contains(bits_of(polygon_t_factor(q))));
  const auto e = polygon_engine(s, q, progress.build());
  ctx.check_cancel();
  const PolygonHeatGeodesic& g = e->geodesic();
  // The heat of every source at once (a point in a triangle of the
  // triangulation: its weights on the triangle's corners, polygon vertices).
  std::vector<double> h(out.size(), 0.0);
  int32_t first = -1;
  for (const SurfacePoint& p : sources) {
    int32_t v[3];
    double w[3];
    const int k = surface_point_support(s.mesh, p, v, w);
    for (int c = 0; c < k; ++c) h[v[c]] += w[c];
    if (first < 0) first = v[0];
  }
  g.solve_heat(h);
  ctx.check_cancel();
  g.distance_from_heat(h, first, std::span<double>(out.data(), out.size()));
  // Per component: shifted so that the minimum over its sources is 0 (session_geodesic.cpp).
  const auto& comp = s.derived->component;
  std::vector<double> shift(static_cast<size_t>(s.derived->components), std::numeric_limits<double>::infinity());
  for (const SurfacePoint& p : sources) {
    int32_t v[3];
    double w[3];
    const int k = surface_point_support(s.mesh, p, v, w);
    double value = 0;
    for (int c = 0; c < k; ++c) value += w[c] * out[v[c]];
    double& m = shift[comp[v[0]]];
    m = std::min(m, value);
  }
  std::vector<char> has_source(shift.size(), 0);
  for (size_t c = 0; c < shift.size(); ++c) has_source[c] = std::isfinite(shift[c]) ? 1 : 0;
  for (size_t i = 0; i < out.size(); ++i)
    if (has_source[comp[i]]) out[i] -= shift[comp[i]];
  finish_distance(s, has_source, out, g.time());
  progress.finish("geodesic distance");
}

LogMapResult polygon_logmap(State& s, int32_t center, int32_t count, const HeatQuery& q, const RunContext& ctx) {
  const CallProgress progress(ctx, !s.polygon_engines.contains(bits_of(polygon_t_factor(q))));
  const auto e = polygon_engine(s, q, progress.build());
  const auto patches = s.polygon_patches.get(0, ctx, [&] {
    auto p = std::make_shared<PolygonPatches>();
    p->adjacency = vertex_adjacency(*s.polygons);
    p->edge_length = adjacency_edge_lengths(*s.polygons, p->adjacency);
    return std::shared_ptr<const PolygonPatches>(std::move(p));
  });
  ctx.check_cancel();
  LogMapResult r;
  GrowWorkspace gws;
  const GrowSeed seed{center, 0.0};
  grow_vertices(patches->adjacency, patches->edge_length, std::span<const GrowSeed>(&seed, 1), geodesic_disk(count),
                gws, r.patch);
  const size_t k = r.patch.size();
  r.distance.resize(k), r.angle.resize(k), r.u.resize(k), r.v.resize(k);
  e->query_full(center, r.patch, {r.distance, r.angle, r.u, r.v});
  check_map_finite(center, r);
  progress.finish("log map");
  return r;
}

}  // namespace session_detail
}  // namespace locus
