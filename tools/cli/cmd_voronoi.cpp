// `locus voronoi MESH`: the heat-diffusion Voronoi diagram of a set of
// generators (thesis §3.4, eqs. 3.15-3.21), computed by locus::Session::voronoi
// (engine/include/locus/engine/voronoi_request.hpp): one factorization of
// M - t L_C, heat of 8 generators per solve, vertex labels by the hottest
// generator, and the diagram's curves as OBJ polylines (`v` and `l` lines) with
// -o. Generators are vertex ids (--sites) or seeded random surface points
// (--random N --seed S).
#include <climits>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "locus/engine/voronoi_request.hpp"
#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

struct VoronoiOptions {
  VoronoiCommandRequest request;
  std::string sites_text;
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
void write_polylines(const std::string& path, const VoronoiCommandReport& D) {
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

Json voronoi_json(const CommonOptions& opt, const Input& in, const VoronoiCommandReport& r) {
  Json j{{"command", "voronoi"}, {"input", input_json(opt, in)}};
  j["n"] = r.n;
  j["sites"] = r.site_xyz.size() / 3;
  j["seed"] = opt.seed;
  j["h"] = r.h;
  j["t"] = r.t;
  j["batches"] = r.batches;
  j["diagram_points"] = r.points.size() / 3;
  j["diagram_segments"] = r.segments;
  j["polylines"] = r.polylines.size();
  j["corners"] = r.corners;
  j["empty_cells"] = r.empty_cells;
  j["vertices_without_heat"] = r.vertices_without_heat;
  j["values_solved_again"] = r.values_solved_again;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["timings"] = timings(in, {{"operator_s", r.operator_s},
                              {"order_s", r.order_s},
                              {"analyze_s", r.analyze_s},
                              {"factor_s", r.factor_s},
                              {"prepare_s", r.prepare_s},
                              {"solve_s", r.solve_s},
                              {"diagram_s", r.diagram_s}});
  return j;
}

int run_voronoi(const CommonOptions& opt, VoronoiOptions& o, const RunContext& ctx) {
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off")
    fail(ErrorCode::BadUsage, "-o " + opt.output + ": OFF cannot hold the diagram's polylines; use .obj or .ply");
  VoronoiCommandRequest& q = o.request;
  q.seed = opt.seed;
  if (!o.sites_text.empty()) {
    const std::vector<int32_t> ids = parse_ids(o.sites_text);
    q.sites.assign(ids.begin(), ids.end());
  }
  check_request(q);
  check_preview_options(o.preview);
  const Input in = load_input(opt, ctx);
  for (size_t k = 0; k < q.sites.size(); ++k)
    if (q.sites[k] >= in.mesh.num_vertices())
      fail(ErrorCode::BadInput, "--sites entry " + std::to_string(k) + " is vertex " + std::to_string(q.sites[k]) +
                                    ", but the mesh has " + std::to_string(in.mesh.num_vertices()) + " vertices");
  const Session session{Mesh(in.mesh), session_options(in)};
  const VoronoiCommandReport r = session.voronoi(q, ctx);
  const size_t ns = r.site_xyz.size() / 3;
  if (!opt.output.empty()) write_polylines(opt.output, r);
  if (!o.preview.path.empty()) {
    PreviewContent pc{"heat voronoi cells of " + std::to_string(ns) + " generators", {}, "generators"};
    for (size_t k = 0; k < ns; ++k) pc.markers.push_back({r.site_xyz[3 * k], r.site_xyz[3 * k + 1], r.site_xyz[3 * k + 2]});
    write_preview(in.mesh, std::vector<double>(r.label.begin(), r.label.end()), PreviewKind::Labels, o.preview, pc);
  }
  emit(opt, voronoi_json(opt, in, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": heat Voronoi diagram of " << ns << " generators on " << r.n << " vertices (t = " << r.t
       << ")\n"
       << "  factor " << r.prepare_s << " s, heat solves " << r.solve_s << " s (" << r.batches
       << " batches of 8), diagram " << r.diagram_s << " s\n"
       << "  " << r.polylines.size() << " polylines, " << r.corners << " corners, " << r.empty_cells
       << " empty cells\n";
    if (r.vertices_without_heat > 0)
      os << "  " << r.vertices_without_heat
         << " vertices received no heat (underflow far from every generator): raise --t\n";
  });
  return 0;
}

}  // namespace

void register_voronoi_command(CommandTable& table) {
  auto o = std::make_shared<VoronoiOptions>();
  CLI::App* app = table.add("voronoi", "Heat-diffusion Voronoi diagram of vertex or random generators (OBJ polylines)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_voronoi(opt, *o, ctx); });
  app->add_option("--sites", o->sites_text, "Generators: comma-separated vertex ids");
  app->add_option("--random", o->request.random, "Generators: N random surface points (seeded by --seed)")
      ->check(CLI::Range(1, 100000000));
  app->add_option("--t", o->request.t, "Diffusion time: absolute (0.001) or a multiple of h^2 (h2, 4h2); default h2")
      ->check(non_empty());
  add_factor_cache_options(app, o->request.save, o->request.load);
  add_preview_option(app, o->preview);
}

}  // namespace locus::cli
