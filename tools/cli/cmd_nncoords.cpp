// `locus nncoords MESH --sites v1,v2,... --point f,b0,b1,b2`: natural-neighbor
// (area-stealing) coordinates of a surface point with respect to vertex sites,
// with heat-diffusion cells (thesis §3.7.2; pipelines/include/locus/pipelines/voronoi/natural_neighbor.hpp).
// JSON: `weights` (one per site, in --sites order), `natural_neighbors` (sites
// with a nonzero weight), `cell_area`, `at_site`, `degenerate`, timings.
#include <ostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/heat_factor_cache.hpp"
#include "tools/cli/site_args.hpp"

namespace locus::cli {
namespace {

struct NnOptions {
  std::string sites_text;
  std::string point_text;
  std::string t_text;
};

int run_nncoords(const CommonOptions& opt, const NnOptions& o, const RunContext& ctx) {
  refuse_output(opt, "nncoords", "the coordinates are in the JSON (--json)");
  if (o.sites_text.empty()) fail(ErrorCode::BadUsage, "--sites is required (comma-separated vertex ids)");
  if (o.point_text.empty()) fail(ErrorCode::BadUsage, "--point is required (FACE,B0,B1,B2)");
  const std::vector<int32_t> ids = parse_vertex_list("--sites", o.sites_text);
  const SurfacePoint given = parse_surface_point("--point", o.point_text);
  const TimeSpec ts = o.t_text.empty() ? TimeSpec{} : parse_time_spec(o.t_text);
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  const std::vector<SurfacePoint> sites = vertex_sites(mesh, "--sites", ids);
  // FACE is a face of the file (a polygon's weights are of its corners 0, 1, 2).
  const SurfacePoint q = point_on_file_face(in, given, "--point");
  check_surface_point(mesh, q, "--point", 0);
  Stopwatch sw;
  const HeatDiffusion H = input_heat_diffusion(in, ts, ctx);  // cotan or robust (--operator)
  const NaturalNeighborField F = prepare_natural_neighbors(H, mesh, sites, ctx);
  const double prepare_s = sw.seconds();
  sw.restart();
  const NaturalCoordinates c = natural_neighbor_coordinates(F, mesh, q);
  const double query_s = sw.seconds();
  std::vector<int32_t> nbrs;
  for (size_t s = 0; s < sites.size(); ++s)
    if (c.weight[s] > 0) nbrs.push_back(ids[s]);
  Json j{{"command", "nncoords"}, {"input", input_json(opt, in)}};
  j["n"] = mesh.num_vertices();
  j["sites"] = ids;
  j["point"] = {given.face, given.bary[0], given.bary[1], given.bary[2]};
  j["t"] = H.t;
  j["weights"] = c.weight;
  j["natural_neighbours"] = nbrs;  // the released JSON key
  j["cell_area"] = c.cell_area;
  j["at_site"] = c.at_site;
  j["degenerate"] = c.degenerate;
  j["clamped"] = c.clamped;
  j["fallback_faces"] = c.fallback_faces;
  j["timings"] = timings(in, {{"prepare_s", prepare_s}, {"query_s", query_s}});
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": natural-neighbor coordinates of face " << q.face << " (" << q.bary[0] << ", "
       << q.bary[1] << ", " << q.bary[2] << ")\n";
    for (size_t s = 0; s < sites.size(); ++s)
      if (c.weight[s] > 0) os << "  vertex " << ids[s] << ": " << c.weight[s] << "\n";
  });
  return 0;
}

}  // namespace

void register_nncoords_command(CommandTable& table) {
  auto o = std::make_shared<NnOptions>();
  CLI::App* app = table.add("nncoords", "Natural-neighbor coordinates of a surface point (heat Voronoi area stealing)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_nncoords(opt, *o, ctx); });
  app->add_option("--sites", o->sites_text, "Sites: comma-separated vertex ids");
  app->add_option("--point", o->point_text,
                  "Query point: FACE,B0,B1,B2 (barycentric weights summing to 1; for a polygon face, weights of its "
                  "corners 0, 1, 2)");
  app->add_option("--t", o->t_text, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default h2")->check(non_empty());
}

}  // namespace locus::cli
