// `locus-bench geodesic-accuracy SPEC`: the whole-mesh heat geodesic distance
// (thesis §6.3; HeatGeodesic::query_full, the `locus geodesic` default) on an
// analytic surface (analytic_surfaces.hpp) against the exact distance.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"
#include "tools/bench/analytic_surfaces.hpp"
#include "tools/bench/bench_centers.hpp"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;

struct GeodesicAccuracyOptions {
  int centers = 1;
  std::string center_ids = "0";
  double t_factor = 0;  // 0: the library's default (triangles: HeatGeodesicOptions, polygons: PolygonHeatGeodesicOptions)
  bool plain_gradient = false;
  double near = 0.5;  // the near-field radius of E_near
  double poisson_rel = HeatGeodesicOptions{}.poisson_rel;
};

// Whole-mesh heat geodesic distance (HeatGeodesic::query_full, the `locus
// geodesic` default) against the exact distance: mean and max over all
// vertices, inside --near, and by exact distance in bands of 0.25; the heat
// values' underflow (zero or subnormal) counted.
int run_geodesic_accuracy(const cli::CommonOptions& opt, const GeodesicAccuracyOptions& go, const RunContext& ctx) {
  const Surface s = make_surface(opt.mesh_path);
  const std::vector<int32_t> centers = accuracy_centers(s, go.center_ids, "random", go.centers, opt.seed);
  const int32_t n = s.mesh.num_vertices();
  HeatGeodesicOptions ho;
  if (go.t_factor > 0) ho.t_factor = go.t_factor;
  ho.log_heat_gradient = !go.plain_gradient;
  ho.poisson_rel = go.poisson_rel;
  Stopwatch sw;
  // Polygon meshes (cube-sphere:N) through the polygon operators, whole mesh only.
  const bool polygons = !s.mesh.is_triangle_mesh();
  std::optional<HeatGeodesic> tri;
  std::optional<PolygonHeatGeodesic> poly;
  if (polygons) {
    PolygonHeatGeodesicOptions po;
    if (go.t_factor > 0) po.t_factor = go.t_factor;
    po.poisson_rel = go.poisson_rel;
    poly.emplace(s.mesh, po, ctx);
  } else {
    tri.emplace(s.mesh, ho, ctx);
  }
  const double h = polygons ? poly->mean_edge_length() : tri->mean_edge_length();
  const double t = polygons ? poly->time() : tri->time();
  const double precompute_s = sw.seconds();
  HeatGeodesicWorkspace ws;
  std::vector<double> d(static_cast<size_t>(n));
  const int nb = 13;  // bands of 0.25 up to pi
  std::vector<double> band_sum(nb, 0.0);
  std::vector<int64_t> band_cnt(nb, 0);
  double mean = 0, maxe = 0, near = 0, query_s = 0;
  int64_t near_cnt = 0, underflow = 0;
  for (int32_t c : centers) {
    ctx.check_cancel();
    sw.restart();
    if (polygons) {
      poly->query_full(c, d);
    } else {
      tri->query_full(c, d, ws);
      underflow += ws.underflow;
    }
    query_s += sw.seconds() / centers.size();
    double sum = 0;
    for (int32_t v = 0; v < n; ++v) {
      const double r = s.exact_distance(c, v), e = std::abs(d[v] - r);
      sum += e;
      maxe = std::max(maxe, e);
      if (r <= go.near) near += e, ++near_cnt;
      const int b = std::min(nb - 1, static_cast<int>(r / 0.25));
      band_sum[b] += e;
      ++band_cnt[b];
    }
    mean += sum / n / centers.size();
  }
  Json bands = Json::array();
  for (int b = 0; b < nb; ++b)
    if (band_cnt[b] > 0)
      bands.push_back(Json{{"from", 0.25 * b}, {"to", 0.25 * (b + 1)}, {"mean_error", band_sum[b] / band_cnt[b]}});
  Json j{{"command", "geodesic-accuracy"}, {"surface", opt.mesh_path}};
  j["n"] = n;
  j["h"] = h;
  j["t"] = t;
  j["t_factor"] = t / (h * h);
  j["polygons"] = polygons;
  j["centers"] = centers;
  j["mean_error"] = mean;
  j["max_error"] = maxe;
  j["near_radius"] = go.near;
  j["mean_error_near"] = near_cnt > 0 ? near / near_cnt : 0.0;
  j["underflow_vertices"] = underflow;
  j["bands"] = bands;
  j["precompute_s"] = precompute_s;
  j["query_s"] = query_s;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

}  // namespace

void register_geodesic_accuracy_bench(cli::CommandTable& table) {
  auto go = std::make_shared<GeodesicAccuracyOptions>();
  CLI::App* geo = table.add(
      "geodesic-accuracy",
      "Whole-mesh heat geodesic distance against the exact one; mesh-file is a surface spec (see logmap-accuracy)",
      [go](const cli::CommonOptions& o, const RunContext& ctx) { return run_geodesic_accuracy(o, *go, ctx); });
  geo->add_option("--center-ids", go->center_ids, "Comma-separated source vertices (default 0)");
  geo->add_option("--t-factor", go->t_factor, "t = c h^2 (default: the library's, 4 for triangles, 8 for polygon meshes)");
  geo->add_flag("--plain-gradient", go->plain_gradient, "Direction from grad h (Crane et al.) instead of grad log h");
  geo->add_option("--poisson-rel", go->poisson_rel, "Regularization of the Poisson operator (HeatGeodesicOptions::poisson_rel)");
  geo->add_option("--near", go->near, "Radius of the near-field error (default 0.5)");
}

}  // namespace locus::bench
