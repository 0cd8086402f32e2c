// `locus perfect-laplacian MESH [--planar] [--iters K] [--eps E] [--method newton|multiplicative]
//  [--anderson M] [--no-active-set] [--noise A] -o out.obj --json`:
// Algorithm 1 of thesis chapter 2 on a polygon mesh; a client of
// locus::Session::perfect_laplacian (engine/include/locus/engine/
// laplacian_requests.hpp), which owns the checks and the computation.
// --method newton (default) reaches its steady state by the interior-point Newton
// method of pipelines/include/locus/pipelines/laplacian/perfect_laplacian_newton.hpp; multiplicative is the update
// of eq. 2.8 with Anderson acceleration (--anderson) and the active set
// (--no-active-set turns it off); those two options act on that method only.
//
// --noise A displaces every vertex by a seeded (--seed) random offset, uniform in
// [-A h, A h] per coordinate (h the mean edge length), before Algorithm 1: the
// robustness test of thesis §2.5 ("added artificial noise"). The noisy mesh is
// then the input (displacements are measured against it).
//
// Output: -o FILE gets the moved mesh — in planar mode the embedding itself (its
// boundary is the fixed one), in space the embedding after the best similarity
// (uniform scale + translation) onto the input, since the scale of a closed
// mesh's embedding is arbitrary. The weights go to the sidecar FILE.weights.txt,
// one line "v0 v1 weight" per unique edge of the faces (0-based input vertex ids,
// v0 < v1, normalized weights with unit 2-norm; 0 where a weight decayed to its
// limit). JSON keys: converged, iterations, min_weight, zero_weights,
// max_displacement_rel, mean_displacement_rel (after alignment, / bbox diagonal),
// first_iter_s (ordering + analysis + factorization + solve + update), iter_s
// (median of the later iterations), iter_ratio = iter_s / first_iter_s; the
// active set of §2.3.3 (pipelines/include/locus/pipelines/laplacian/weight_active_set.hpp): weights_at_floor
// (exactly 0), weights_revived, kkt_rounds, kkt_violation (max log-length
// excess of a zero-weight edge over the common ratio; <= 1e-4 when steady);
// method, factorizations (line-search trials included), hessian_products (Newton:
// CG steps, one solve each).
#include <iomanip>
#include <ostream>
#include <string>

#include "locus/engine/laplacian_requests.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

void write_weights(const std::string& path, const PerfectLaplacianCommandReport& r) {
  io::write_file_atomically(path, [&](std::ostream& os) {
    os << std::setprecision(17);
    for (size_t e = 0; e < r.weights.size(); ++e)
      os << r.edges[2 * e] << ' ' << r.edges[2 * e + 1] << ' ' << r.weights[e] << '\n';
  });
}

Json perfect_laplacian_json(const CommonOptions& opt, const Input& in, const PerfectLaplacianCommandRequest& q,
                            const PerfectLaplacianCommandReport& r) {
  Json j{{"command", "perfect-laplacian"}, {"input", input_json(opt, in)}};
  j["mode"] = r.mode;
  j["boundary_loops"] = r.boundary_loops;
  j["boundary_on_circle"] = r.boundary_on_circle;
  j["pinned_vertices"] = r.pinned_vertices;
  j["n_edges"] = r.weights.size();
  j["converged"] = r.converged;
  j["iterations"] = r.iterations;
  j["last_change_rel"] = r.last_change_rel;
  j["min_weight"] = r.min_weight;
  j["min_positive_weight"] = r.min_positive_weight;
  j["zero_weights"] = r.zero_weights;
  j["weights_at_floor"] = r.weights_at_floor;
  j["weights_revived"] = r.weights_revived;
  j["kkt_rounds"] = r.kkt_rounds;
  j["kkt_violation"] = r.kkt_violation;
  j["active_set"] = !q.no_active_set;
  j["noise"] = q.noise;
  j["max_displacement_rel"] = r.max_displacement_rel;
  j["mean_displacement_rel"] = r.mean_displacement_rel;
  j["align_scale"] = r.align_scale;
  j["anderson_depth"] = q.anderson;
  j["method"] = q.method;
  j["factorizations"] = r.factorizations;
  j["hessian_products"] = r.hessian_products;
  j["order_s"] = r.order_s;
  j["analyze_s"] = r.analyze_s;
  j["first_iter_s"] = r.first_iter_s;
  j["iter_s"] = r.iter_s;
  j["iter_ratio"] = r.first_iter_s > 0 ? r.iter_s / r.first_iter_s : 0.0;
  j["timings"] = timings(in, {{"rhs_s", r.rhs_s}, {"total_s", r.total_s}});
  if (!opt.output.empty()) j["weights_file"] = opt.output + ".weights.txt";
  return j;
}

int run(const CommonOptions& opt, PerfectLaplacianCommandRequest& q, const RunContext& ctx) {
  q.seed = opt.seed;
  check_request(q);
  const Input in = load_input(opt, ctx, PolygonFaces::Keep);
  const Session session{Mesh(in.mesh), session_options(in)};
  const PerfectLaplacianCommandReport r = session.perfect_laplacian(q, ctx);
  if (!opt.output.empty()) {
    Mesh out = in.mesh;
    for (int32_t v = 0; v < out.num_vertices(); ++v)
      out.x[v] = r.xyz[3 * size_t(v)], out.y[v] = r.xyz[3 * size_t(v) + 1], out.z[v] = r.xyz[3 * size_t(v) + 2];
    write_output_mesh(opt, out, carried_attributes(in, /*positions_changed=*/true));
    write_weights(opt.output + ".weights.txt", r);
  }
  emit(opt, perfect_laplacian_json(opt, in, q, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": perfect Laplacian (" << r.mode << (r.boundary_on_circle ? ", boundary on a circle" : "")
       << ")\n  " << (r.converged ? "converged" : "NOT converged") << " after " << r.iterations << " iterations\n"
       << "  min weight " << r.min_weight << ", " << r.zero_weights << " numerically zero of " << r.weights.size()
       << "\n  displacement after similarity alignment: max " << r.max_displacement_rel << ", mean "
       << r.mean_displacement_rel << " of the bbox diagonal\n  first iteration " << r.first_iter_s
       << " s, later iterations (median) " << r.iter_s << " s\n";
  });
  return 0;  // not converging within --iters is a result (reported), not an error
}

}  // namespace

void register_perfect_laplacian_command(CommandTable& table);

// The chapter-2 commands live in their own files; one registration entry point
// (declared in cli_common.hpp) adds all three.
void register_param_command(CommandTable& table);        // cmd_param.cpp
void register_selfsupport_command(CommandTable& table);  // cmd_selfsupport.cpp

void register_perfect_laplacian_commands(CommandTable& table) {
  register_perfect_laplacian_command(table);
  register_param_command(table);
  register_selfsupport_command(table);
}

void register_perfect_laplacian_command(CommandTable& table) {
  auto po = std::make_shared<PerfectLaplacianCommandRequest>();
  CLI::App* app = table.add(
      "perfect-laplacian",
      "Algorithm 1 (thesis ch. 2): a perfect Laplacian and the nearby mesh it belongs to; weights to OUT.weights.txt",
      [po](const CommonOptions& opt, const RunContext& ctx) { return run(opt, *po, ctx); });
  app->add_flag("--planar", po->planar, "Treat the mesh as planar (use x, y; boundary fixed in convex position)");
  app->add_option("--iters", po->iters, "Iteration cap (default 1000)")->check(CLI::Range(1, 1000000));
  app->add_option("--eps", po->eps, "Stop when no vertex moves more than eps * bbox diagonal (default 1e-6)")
      ->check(CLI::PositiveNumber);
  app->add_option("--method", po->method,
                  "newton (default: interior-point Newton on the concave dual) or multiplicative (eq. 2.8)")
      ->check(CLI::IsMember({"newton", "multiplicative"}));
  app->add_option("--anderson", po->anderson, "Anderson acceleration depth, 0 = plain update (default 6)")
      ->check(CLI::Range(0, 50));
  app->add_option("--noise", po->noise,
                  "Displace vertices by seeded uniform noise of up to A * mean edge length per coordinate first")
      ->check(CLI::NonNegativeNumber);
  app->add_flag("--no-active-set", po->no_active_set,
                "Keep iterating every weight (no dropping of geometrically decaying weights, thesis 2.3.3)");
}

}  // namespace locus::cli
