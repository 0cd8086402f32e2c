// `locus voronoi MESH`: the heat-diffusion Voronoi diagram of a set of
// generators (thesis §3.4, eqs. 3.15-3.21; pipelines/include/locus/pipelines/voronoi/heat_voronoi.hpp): one
// factorization of M - t L_C, heat of 8 generators per solve, vertex labels by
// the hottest generator, and the diagram's curves as OBJ polylines (`v` and `l`
// lines) with -o. Generators are vertex ids (--sites) or seeded random surface
// points (--random N --seed S).
#include <algorithm>
#include <climits>
#include <fstream>
#include <sstream>
#include <ostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "tools/cli/cli_common.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "tools/cli/heat_factor_cache.hpp"

namespace locus::cli {
namespace {

struct VoronoiOptions {
  std::string sites_text;
  int32_t random = 0;
  std::string t_text;
  FactorCacheOptions fc;
  PreviewOptions preview;
};

std::vector<int32_t> parse_ids(const std::string& text) {
  std::vector<int32_t> ids;
  const std::string msg = "--sites expects comma-separated vertex ids (e.g. --sites 0,17,342), got '" + text + "'";
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    const std::string part = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t used = 0;
    long long v = -1;
    try {
      v = std::stoll(part, &used);
    } catch (const std::exception&) {
      fail(ErrorCode::BadUsage, msg);
    }
    if (used != part.size() || v < 0 || v > INT32_MAX) fail(ErrorCode::BadUsage, msg);
    ids.push_back(static_cast<int32_t>(v));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return ids;
}

// The diagram's bisector polylines: OBJ `l` lines, or PLY vertices plus an
// `edge` element (vertex1, vertex2), which MeshLab and Blender's importer read.
void write_polylines(const std::string& path, const VoronoiDiagram& D) {
  std::ostringstream os;
  os.precision(17);
  const size_t np = D.points.size() / 3;
  if (io::lower_extension(path) == "ply") {
    size_t edges = 0;
    for (const auto& line : D.polylines) edges += line.size() > 1 ? line.size() - 1 : 0;
    os << "ply\nformat ascii 1.0\ncomment heat Voronoi diagram (locus voronoi): bisector polylines\nelement vertex "
       << np << "\nproperty double x\nproperty double y\nproperty double z\nelement edge " << edges
       << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    for (size_t p = 0; p < np; ++p) os << D.points[3 * p] << ' ' << D.points[3 * p + 1] << ' ' << D.points[3 * p + 2] << '\n';
    for (const auto& line : D.polylines)
      for (size_t k = 1; k < line.size(); ++k) os << line[k - 1] << ' ' << line[k] << '\n';
  } else {
    os << "# heat Voronoi diagram (locus voronoi): " << np << " points, " << D.polylines.size() << " polylines\n";
    for (size_t p = 0; p < np; ++p)
      os << "v " << D.points[3 * p] << ' ' << D.points[3 * p + 1] << ' ' << D.points[3 * p + 2] << '\n';
    for (const auto& line : D.polylines) {
      os << 'l';
      for (int32_t p : line) os << ' ' << p + 1;
      os << '\n';
    }
  }
  io::write_file_atomically(path, os.str());
}

int run_voronoi(const CommonOptions& opt, const VoronoiOptions& o, const RunContext& ctx) {
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off")
    fail(ErrorCode::BadUsage, "-o " + opt.output + ": OFF cannot hold the diagram's polylines; use .obj or .ply");
  if (o.sites_text.empty() == (o.random <= 0)) fail(ErrorCode::BadUsage, "give either --sites or --random N (N > 0)");
  const TimeSpec ts = o.t_text.empty() ? TimeSpec{} : parse_time_spec(o.t_text);
  validate_factor_cache_options(o.fc);
  check_preview_options(o.preview);
  const std::vector<int32_t> ids = o.sites_text.empty() ? std::vector<int32_t>{} : parse_ids(o.sites_text);
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  std::vector<SurfacePoint> sites;
  for (size_t k = 0; k < ids.size(); ++k) {
    if (ids[k] >= mesh.num_vertices())
      fail(ErrorCode::BadInput, "--sites entry " + std::to_string(k) + " is vertex " + std::to_string(ids[k]) +
                                    ", but the mesh has " + std::to_string(mesh.num_vertices()) + " vertices");
    sites.push_back(vertex_point(ids[k]));
  }
  ctx.check_cancel();
  Stopwatch sw;
  // Requirements are checked inside; t as a multiple of h^2 needs h first.
  Factors cache;
  const HeatDiffusion H = heat_diffusion_cached(o.fc, in, ts, ctx, cache);
  const double prepare_s = sw.seconds();
  if (o.random > 0) sites = random_surface_points(mesh, o.random, opt.seed);
  if (static_cast<int64_t>(sites.size()) > mesh.num_vertices())
    fail(ErrorCode::BadInput, "more generators than vertices");
  ctx.check_cancel();
  sw.restart();
  const HeatVoronoi V = heat_voronoi(H, mesh, sites, {}, {}, ctx);
  const double solve_s = sw.seconds();
  sw.restart();
  const VoronoiDiagram D = extract_voronoi_diagram(H, mesh, sites, V, ctx);
  const double diagram_s = sw.seconds();
  std::vector<int64_t> cell_size(sites.size(), 0);
  for (int32_t l : V.label) ++cell_size[l];
  const int64_t empty = std::count(cell_size.begin(), cell_size.end(), 0);
  // Heat decays like exp(-r / sqrt(t)) and underflows to 0 far from every generator
  // (small t, few generators); such vertices are labelled by the smallest generator id,
  // which makes noisy cells: report them so the user can raise --t.
  int64_t cold = 0;
  for (int32_t v = 0; v < mesh.num_vertices(); ++v) cold += !(V.top_value[static_cast<size_t>(v) * kVoronoiTopK] > 0);

  if (!opt.output.empty()) write_polylines(opt.output, D);
  if (!o.preview.path.empty()) {
    PreviewContent pc{"heat voronoi cells of " + std::to_string(sites.size()) + " generators", {}, "generators"};
    for (const SurfacePoint& p : sites) pc.markers.push_back(surface_point_position(mesh, p));
    write_preview(mesh, std::vector<double>(V.label.begin(), V.label.end()), PreviewKind::Labels, o.preview, pc);
  }
  Json j{{"command", "voronoi"}, {"input", input_json(opt, in)}};
  j["n"] = mesh.num_vertices();
  j["sites"] = sites.size();
  j["seed"] = opt.seed;
  j["h"] = H.h;
  j["t"] = H.t;
  j["batches"] = V.batches;
  j["diagram_points"] = D.points.size() / 3;
  j["diagram_segments"] = D.segments.size() / 2;
  j["polylines"] = D.polylines.size();
  j["corners"] = D.corners;
  j["empty_cells"] = empty;
  j["vertices_without_heat"] = cold;
  j["values_solved_again"] = D.resolved_missing;
  j["factor_cache"] = factor_cache_json(o.fc, cache);
  j["timings"] = timings(in, {{"operator_s", H.operator_s},
                  {"order_s", H.order_s},     {"analyze_s", H.analyze_s},      {"factor_s", H.factor_s},
                  {"prepare_s", prepare_s},   {"solve_s", solve_s},            {"diagram_s", diagram_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": heat Voronoi diagram of " << sites.size() << " generators on " << mesh.num_vertices()
       << " vertices (t = " << H.t << ")\n"
       << "  factor " << prepare_s << " s, heat solves " << solve_s << " s (" << V.batches << " batches of 8), diagram "
       << diagram_s << " s\n"
       << "  " << D.polylines.size() << " polylines, " << D.corners << " corners, " << empty << " empty cells\n";
    if (cold > 0)
      os << "  " << cold << " vertices received no heat (underflow far from every generator): raise --t\n";
  });
  return 0;
}

}  // namespace

void register_voronoi_command(CommandTable& table) {
  auto o = std::make_shared<VoronoiOptions>();
  CLI::App* app = table.add("voronoi", "Heat-diffusion Voronoi diagram of vertex or random generators (OBJ polylines)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_voronoi(opt, *o, ctx); });
  app->add_option("--sites", o->sites_text, "Generators: comma-separated vertex ids");
  app->add_option("--random", o->random, "Generators: N random surface points (seeded by --seed)")
      ->check(CLI::Range(1, 100000000));
  app->add_option("--t", o->t_text, "Diffusion time: absolute (0.001) or a multiple of h^2 (h2, 4h2); default h2")->check(non_empty());
  add_factor_cache_options(app, o->fc);
  add_preview_option(app, o->preview);
}

}  // namespace locus::cli
