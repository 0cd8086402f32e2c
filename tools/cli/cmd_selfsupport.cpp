// `locus selfsupport MESH --support boundary [--load-density D] -o out.obj --json`:
// a self-supporting surface near the input (thesis §2.6, eq. 2.12;
// pipelines/self_supporting): compression-only strut forces in equilibrium with
// a dead load proportional to vertex area, supports on the boundary.
//
// -o FILE writes the equilibrium surface and FILE.forces.txt with lines
// "v0 v1 force" (0-based vertex ids, v0 < v1, force in load units, >= 0).
// JSON: converged, iterations, residual_rel (max force imbalance / max load),
// min_force, max_force, zero_forces, max/mean_displacement_rel, timings.
#include <fstream>
#include <iomanip>
#include <ostream>

#include "locus/pipelines/laplacian/self_supporting.hpp"
#include "tools/cli/cli_common.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"

namespace locus::cli {
namespace {

struct SelfSupportCliOptions {
  std::string support = "boundary";
  double load_density = 1.0;
  int iters = 1000;
  double eps = 1e-6;
};

int run_selfsupport(const CommonOptions& opt, const SelfSupportCliOptions& so, const RunContext& ctx) {
  if (so.support != "boundary") fail(ErrorCode::BadUsage, "--support: only 'boundary' is supported");
  Input in = load_input(opt, ctx, PolygonFaces::Keep);
  SelfSupportOptions o;
  o.support = so.support;
  o.load_density = so.load_density;
  o.iteration.max_iterations = so.iters;
  o.iteration.eps = so.eps;
  const SelfSupportResult r = self_supporting(in.mesh, o, ctx);
  if (!opt.output.empty()) {
    Mesh out = in.mesh;
    out.x = r.pos[0];
    out.y = r.pos[1];
    out.z = r.pos[2];
    write_output_mesh(opt, out, carried_attributes(in, /*positions_changed=*/true));
    io::write_file_atomically(opt.output + ".forces.txt", [&](std::ostream& os) {
      os << std::setprecision(17);
      for (size_t e = 0; e < r.e0.size(); ++e) os << r.e0[e] << ' ' << r.e1[e] << ' ' << r.forces[e] << '\n';
    });
  }
  Json j{{"command", "selfsupport"}, {"input", input_json(opt, in)}};
  j["support"] = so.support;
  j["load_density"] = so.load_density;
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
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": self-supporting surface, " << (r.converged ? "converged" : "NOT converged") << " after "
       << r.iterations << " iterations\n  equilibrium residual " << r.residual_rel << " of the largest load, forces in ["
       << r.min_force << ", " << r.max_force << "]\n  displacement max " << r.max_displacement_rel << ", mean "
       << r.mean_displacement_rel << " of the bbox diagonal\n";
  });
  return 0;
}

}  // namespace

void register_selfsupport_command(CommandTable& table) {
  auto so = std::make_shared<SelfSupportCliOptions>();
  CLI::App* app = table.add("selfsupport", "Self-supporting surface (thesis 2.6): compression-only equilibrium under dead load",
                            [so](const CommonOptions& opt, const RunContext& ctx) { return run_selfsupport(opt, *so, ctx); });
  app->add_option("--support", so->support, "Supported vertices: boundary (default)");
  app->add_option("--load-density", so->load_density, "Dead load per unit area (default 1)")->check(CLI::PositiveNumber);
  app->add_option("--iters", so->iters, "Iteration cap (default 1000)")->check(CLI::Range(1, 1000000));
  app->add_option("--eps", so->eps, "Tolerance (default 1e-6 of the diagonal)")->check(CLI::PositiveNumber);
}

}  // namespace locus::cli
