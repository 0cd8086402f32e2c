// `locus deform MESH --roi-seed V --handle H --offset dx,dy,dz`: region-of-
// interest deformation with a factor-once submesh factor (thesis §5.1, §5.7);
// a client of locus::Session::deform (engine/include/locus/engine/
// deform_request.hpp), which owns the validation and the computation. The
// global operator is factored once; the factor of A_FF for the free vertices
// comes from the update kernel; the handle offset is then one 8-lane solve.
// For comparison the same A_FF is ordered (METIS), analyzed and factored from
// scratch and solved again: `refactor_s` / `refactor_solve_s`, and the
// largest coordinate difference of the two results is reported.
#include <array>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "locus/engine/deform_request.hpp"
#include "locus/error.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

struct DeformCli {
  DeformCommandRequest request;
  std::string offset_text;  // --offset dx,dy,dz as given
};

std::array<double, 3> parse_offset(const std::string& text) {
  const std::string msg = "--offset expects three finite numbers dx,dy,dz (e.g. --offset=-0.1,0,0.2), got '" + text + "'";
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (parts.size() != 3) fail(ErrorCode::BadUsage, msg);
  std::array<double, 3> v{};
  for (int k = 0; k < 3; ++k) {
    size_t used = 0;
    try {
      v[k] = std::stod(parts[k], &used);
    } catch (const std::exception&) {
      fail(ErrorCode::BadUsage, msg);
    }
    if (used != parts[k].size() || !std::isfinite(v[k])) fail(ErrorCode::BadUsage, msg);
  }
  return v;
}

Json deform_json(const CommonOptions& opt, const Input& in, const DeformCommandRequest& q,
                 const DeformCommandReport& r) {
  Json j{{"command", "deform"}, {"input", input_json(opt, in)}};
  j["energy"] = r.energy;
  j["regularization"] = q.regularization;
  j["roi_seed"] = q.roi_seed;
  j["roi_fraction"] = q.roi_fraction;
  j["handle"] = q.handle;
  j["handle_ring"] = q.handle_ring;
  j["offset"] = {q.offset[0], q.offset[1], q.offset[2]};
  j["threads"] = threads_used(opt);
  j["n"] = r.n;
  j["roi_vertices"] = r.roi_vertices;
  j["handle_vertices"] = r.handle_vertices;
  j["free_vertices"] = r.free_vertices;
  j["fixed_vertices"] = static_cast<int64_t>(r.n) - static_cast<int64_t>(r.roi_vertices);
  j["global_factor_s"] = r.order_s + r.analyze_s + r.factor_s;
  j["update_s"] = r.update_s;
  j["system_s"] = r.system_s;
  j["solve_s"] = r.solve_s;
  j["refactor_s"] = r.refactor_s;
  j["refactor_solve_s"] = r.refactor_solve_s;
  j["speedup_update_vs_refactor"] = r.update_s > 0 ? r.refactor_s / r.update_s : 0.0;
  j["columns_updated_fraction"] = r.columns_updated_fraction;
  j["supernodes_recomputed"] = r.supernodes_recomputed;
  j["supernodes"] = r.supernodes;
  j["values_stored_update"] = r.values_stored_update;
  j["values_stored_refactor"] = r.values_stored_refactor;
  j["refinement_steps"] = r.refinement_steps;
  j["residual"] = r.residual;
  j["max_displacement"] = r.max_displacement;
  j["update_vs_refactor_max_diff"] = r.update_vs_refactor_max_diff;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  if (!r.warnings.empty()) j["warnings"] = r.warnings;
  j["timings"] = timings(in, {{"operator_s", r.operator_s},
                              {"order_s", r.order_s},
                              {"analyze_s", r.analyze_s},
                              {"factor_s", r.factor_s},
                              {"region_s", r.region_s},
                              {"update_structure_s", r.update_structure_s},
                              {"update_mark_s", r.update_mark_s},
                              {"update_copy_s", r.update_copy_s},
                              {"update_factor_s", r.update_factor_s}});
  return j;
}

int run_deform(const CommonOptions& opt, DeformCli& o, const RunContext& ctx) {
  DeformCommandRequest& q = o.request;
  q.offset = parse_offset(o.offset_text);
  check_request(q);
  const Input in = load_input(opt, ctx);
  // Ids beyond the file's vertices: the refusal depends on the file (exit 3), before the global factorization.
  const int32_t nv = in.mesh.num_vertices();
  for (const auto& [name, v] : {std::pair<const char*, int64_t>{"--roi-seed", q.roi_seed}, {"--handle", q.handle}})
    if (v >= nv)
      fail(ErrorCode::BadInput, std::string(name) + " " + std::to_string(v) +
                                    " is not a vertex id (the mesh has " + std::to_string(nv) + " vertices)");
  const Session session{Mesh(in.mesh), session_options(in)};
  const DeformCommandReport r = session.deform(q, ctx, /*compare_with_refactor=*/true);
  const Json j = deform_json(opt, in, q, r);
  for (const std::string& w : r.warnings) log("warning: " + w);
  Mesh out = in.mesh;
  for (int32_t v = 0; v < nv; ++v)
    out.x[v] = r.xyz[3 * static_cast<size_t>(v)], out.y[v] = r.xyz[3 * static_cast<size_t>(v) + 1],
    out.z[v] = r.xyz[3 * static_cast<size_t>(v) + 2];
  write_output_mesh(opt, with_positions(in, out), carried_attributes(in, /*positions_changed=*/true));
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": " << r.energy << " deformation, " << nv << " vertices; ROI " << r.roi_vertices
       << " (handle " << r.handle_vertices << ", free " << r.free_vertices << ")\n"
       << "  global factor " << j["global_factor_s"] << " s (once per mesh)\n"
       << "  update " << r.update_s << " s (" << 100.0 * r.columns_updated_fraction
       << "% of columns recomputed), solve " << r.solve_s << " s (" << r.refinement_steps
       << " refinement steps, residual " << r.residual << ")\n"
       << "  from scratch: analyze+factor " << r.refactor_s << " s, solve " << r.refactor_solve_s
       << " s; max difference " << r.update_vs_refactor_max_diff << "\n";
  });
  return 0;
}

}  // namespace

void register_deform_command(CommandTable& table) {
  auto o = std::make_shared<DeformCli>();
  CLI::App* app = table.add("deform", "Move a handle inside a region of interest (factor-once submesh update)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_deform(opt, *o, ctx); });
  DeformCommandRequest& q = o->request;
  app->add_option("--roi-seed", q.roi_seed, "Vertex the region of interest grows from (BFS)")->required();
  app->add_option("--roi-fraction", q.roi_fraction, "Fraction of the vertices in the region of interest (default 0.1)")
      ->check(CLI::Range(0.0, 1.0));
  app->add_option("--handle", q.handle, "Handle vertex (inside the region of interest)")->required();
  app->add_option("--handle-ring", q.handle_ring, "Handle = the handle vertex and its k-ring in the ROI (default 1)")
      ->check(CLI::Range(0, 1000));
  app->add_option("--offset", o->offset_text, "Handle displacement dx,dy,dz")->required();
  app->add_option("--energy", q.energy, "laplacian (default) or bilaplacian");
  app->add_option("--regularization", q.regularization,
                  "Relative eps of -L_C + eps M in the factored global operator (default 1e-6); the solve "
                  "refines to the exact energy");
  add_factor_cache_options(app, q.save, q.load);
}

}  // namespace locus::cli
