// `locus nncoords MESH --sites v1,v2,... --point f,b0,b1,b2`: natural-neighbor
// (area-stealing) coordinates of a surface point with respect to vertex sites,
// with heat-diffusion cells (thesis §3.7.2); a client of locus::Session::nncoords
// (engine/include/locus/engine/nncoords_request.hpp), which owns the computation.
// JSON: `weights` (one per site, in --sites order), `natural_neighbors` (sites
// with a nonzero weight), `cell_area`, `at_site`, `degenerate`, timings.
#include <ostream>
#include <string>
#include <vector>

#include "locus/engine/nncoords_request.hpp"
#include "locus/error.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/site_args.hpp"

namespace locus::cli {
namespace {

struct NnOptions {
  NncoordsRequest request;
  std::string sites_text;
  std::string point_text;
};

Json nncoords_json(const CommonOptions& opt, const Input& in, const SurfacePoint& given, const NncoordsRequest& q,
                   const NncoordsReport& r) {
  Json j{{"command", "nncoords"}, {"input", input_json(opt, in)}};
  j["n"] = in.mesh.num_vertices();
  j["sites"] = q.sites;
  j["point"] = {given.face, given.bary[0], given.bary[1], given.bary[2]};
  j["t"] = r.t;
  j["weights"] = r.weights;
  j["natural_neighbours"] = r.natural_neighbors;  // the released JSON key
  j["cell_area"] = r.cell_area;
  j["at_site"] = r.at_site;
  j["degenerate"] = r.degenerate;
  j["clamped"] = r.clamped;
  j["fallback_faces"] = r.fallback_faces;
  j["timings"] = timings(in, {{"prepare_s", r.prepare_s}, {"query_s", r.query_s}});
  return j;
}

int run_nncoords(const CommonOptions& opt, NnOptions& o, const RunContext& ctx) {
  refuse_output(opt, "nncoords", "the coordinates are in the JSON (--json)");
  if (o.sites_text.empty()) fail(ErrorCode::BadUsage, "--sites is required (comma-separated vertex ids)");
  if (o.point_text.empty()) fail(ErrorCode::BadUsage, "--point is required (FACE,B0,B1,B2)");
  NncoordsRequest& q = o.request;
  const std::vector<int32_t> ids = parse_vertex_list("--sites", o.sites_text);
  q.sites.assign(ids.begin(), ids.end());
  const SurfacePoint given = parse_surface_point("--point", o.point_text);
  q.point = {given.face, given.bary};
  check_request(q);
  const Input in = load_input(opt, ctx);
  vertex_sites(in.mesh, "--sites", ids);  // ids beyond the file's vertices: exit 3
  // FACE is a face of the file (a polygon's weights are of its corners 0, 1, 2).
  const SurfacePoint p = point_on_file_face(in, given, "--point");
  check_surface_point(in.mesh, p, "--point", 0);
  q.point = {p.face, p.bary};
  const Session session{Mesh(in.mesh), session_options(in)};
  const NncoordsReport r = session.nncoords(q, ctx);
  emit(opt, nncoords_json(opt, in, given, q, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": natural-neighbor coordinates of face " << p.face << " (" << p.bary[0] << ", "
       << p.bary[1] << ", " << p.bary[2] << ")\n";
    for (size_t s = 0; s < ids.size(); ++s)
      if (r.weights[s] > 0) os << "  vertex " << ids[s] << ": " << r.weights[s] << "\n";
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
  app->add_option("--t", o->request.t, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default h2")->check(non_empty());
}

}  // namespace locus::cli
