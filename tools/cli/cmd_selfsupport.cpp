// `locus selfsupport MESH --support boundary [--load-density D] -o out.obj --json`:
// a self-supporting surface near the input (thesis §2.6, eq. 2.12), by
// locus::Session::self_supporting (engine/include/locus/engine/
// laplacian_requests.hpp): compression-only strut forces in equilibrium with
// a dead load proportional to vertex area, supports on the boundary.
//
// -o FILE writes the equilibrium surface and FILE.forces.txt with lines
// "v0 v1 force" (0-based vertex ids, v0 < v1, force in load units, >= 0).
// JSON: converged, iterations, residual_rel (max force imbalance / max load),
// min_force, max_force, zero_forces, max/mean_displacement_rel, timings.
#include <iomanip>
#include <ostream>

#include "locus/engine/laplacian_requests.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

Json selfsupport_json(const CommonOptions& opt, const Input& in, const SelfSupportCommandRequest& q,
                      const SelfSupportCommandReport& r) {
  Json j{{"command", "selfsupport"}, {"input", input_json(opt, in)}};
  j["support"] = q.support;
  j["load_density"] = q.load_density;
  j["converged"] = r.converged;
  j["iterations"] = r.iterations;
  j["residual_rel"] = r.residual_rel;
  j["min_force"] = r.min_force;
  j["max_force"] = r.max_force;
  j["zero_forces"] = r.zero_forces;
  j["max_displacement_rel"] = r.max_displacement_rel;
  j["mean_displacement_rel"] = r.mean_displacement_rel;
  j["first_iter_s"] = r.first_iter_s;
  j["iter_s"] = r.iter_s;
  j["timings"] = timings(in, {{"total_s", r.total_s}});
  return j;
}

int run_selfsupport(const CommonOptions& opt, const SelfSupportCommandRequest& q, const RunContext& ctx) {
  check_request(q);
  const Input in = load_input(opt, ctx, PolygonFaces::Keep);
  const Session session{Mesh(in.mesh), session_options(in)};
  const SelfSupportCommandReport r = session.self_supporting(q, ctx);
  if (!opt.output.empty()) {
    Mesh out = in.mesh;
    for (int32_t v = 0; v < out.num_vertices(); ++v)
      out.x[v] = r.xyz[3 * size_t(v)], out.y[v] = r.xyz[3 * size_t(v) + 1], out.z[v] = r.xyz[3 * size_t(v) + 2];
    write_output_mesh(opt, out, carried_attributes(in, /*positions_changed=*/true));
    io::write_file_atomically(opt.output + ".forces.txt", [&](std::ostream& os) {
      os << std::setprecision(17);
      for (size_t e = 0; e < r.forces.size(); ++e)
        os << r.edges[2 * e] << ' ' << r.edges[2 * e + 1] << ' ' << r.forces[e] << '\n';
    });
  }
  emit(opt, selfsupport_json(opt, in, q, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": self-supporting surface, " << (r.converged ? "converged" : "NOT converged") << " after "
       << r.iterations << " iterations\n  equilibrium residual " << r.residual_rel
       << " of the largest load, forces in [" << r.min_force << ", " << r.max_force << "]\n  displacement max "
       << r.max_displacement_rel << ", mean " << r.mean_displacement_rel << " of the bbox diagonal\n";
  });
  return 0;
}

}  // namespace

void register_selfsupport_command(CommandTable& table) {
  auto so = std::make_shared<SelfSupportCommandRequest>();
  CLI::App* app = table.add("selfsupport", "Self-supporting surface (thesis 2.6): compression-only equilibrium under dead load",
                            [so](const CommonOptions& opt, const RunContext& ctx) { return run_selfsupport(opt, *so, ctx); });
  app->add_option("--support", so->support, "Supported vertices: boundary (default)");
  app->add_option("--load-density", so->load_density, "Dead load per unit area (default 1)")->check(CLI::PositiveNumber);
  app->add_option("--iters", so->iters, "Iteration cap (default 1000)")->check(CLI::Range(1, 1000000));
  app->add_option("--eps", so->eps, "Tolerance (default 1e-6 of the diagonal)")->check(CLI::PositiveNumber);
}

}  // namespace locus::cli
