// The patch mode of `locus param` (tools/cli/param_patch.hpp): thesis §4.4.
//
// The whole mesh's regularized cotan Laplacian -L_C + eps M is ordered and
// factored once (by locus::Session::param, engine/include/locus/engine/
// param_request.hpp); the patch is the BFS patch of round(fraction * n)
// vertices around --center (kernels/mesh/patch_grower, Rings mode); its boundary loop on a circle gives the
// Neumann data of eq. 4.6; u and v come from one 8-lane subset solve with the
// patch vertices as the wanted set (exact: the full solve's values there), then
// are centered and scaled into the unit disk. --method does not apply: the patch
// mode always uses the global cotan operator (that is the point of §4.4).
//
// -o FILE writes the PATCH as a mesh of its own (vertex k = k-th patch vertex)
// with the parameterization as texture coordinates (OBJ `vt`, PLY u/v).
// JSON: n, factor_s (order + symbolic + numeric of the global operator),
// query_s (patch growing + data + subset solve + normalization + flip check),
// the patch and boundary sizes, Euler characteristic, flipped / degenerate
// faces (orientation against the majority), the columns of L the solve visited.
// --save F / --load F keep the global factor in a factor cache.
//
// --boundary circle: the same patch with enclosed holes filled, its boundary
// loop FIXED on a circle (arc length), the interior's factor from the global
// factor by the factor-once update (pipelines/.../patch_param_circle): the harmonic
// map with convex boundary, flip-free where the cotan weights are positive.
// JSON adds holes_filled, vertices_added, refinement_steps and the update's
// columns; query_s = growing + system + update + solve + checks.
#include <ostream>

#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tools/cli/param_patch.hpp"
#include "tools/cli/written_files.hpp"

namespace locus::cli {

namespace {

Json patch_json(const CommonOptions& opt, const Input& in, const ParamRequest& q, const ParamReport& r) {
  const bool circle = q.boundary == "circle";
  Json j{{"command", "param"}, {"input", input_json(opt, in)}};
  j["domain"] = "patch";
  j["boundary"] = q.boundary;
  j["operator"] = circle ? "cotan Laplacian, patch boundary fixed on a circle; factor of the interior by the "
                           "factor-once update of the global -L_C + eps M, eps removed by preconditioned CG"
                         : "regularized cotan Laplacian of the whole mesh (-L_C + eps M), Neumann data of eq. 4.6";
  j["n"] = r.n;
  j["center"] = q.center;
  j["fraction"] = q.fraction;
  j["patch_vertices"] = r.patch_vertices.size();
  j["patch_faces"] = r.patch_faces;
  j["bfs_rings"] = r.bfs_rings;
  j["boundary_vertices"] = r.boundary_vertices;
  j["boundary_loops"] = r.boundary_loops;
  if (circle) {
    j["holes_filled"] = r.holes_filled;
    j["vertices_added"] = r.vertices_added;
  }
  j["euler_characteristic"] = r.euler_characteristic;
  if (circle) {
    j["interior_vertices"] = r.interior_vertices;
    j["refinement_steps"] = r.refinement_steps;
  }
  j["flipped_faces"] = r.flipped_faces;
  j["degenerate_faces"] = r.degenerate_faces;
  j["orientation"] = r.orientation;
  j["etree_height"] = r.etree_height;
  if (circle) {
    j["update"] = {{"supernodes", r.update_supernodes},
                   {"supernodes_recomputed", r.update_supernodes_recomputed},
                   {"columns_recomputed", r.update_columns_recomputed},
                   {"values_stored", r.update_values_stored}};
  } else {
    j["forward_columns"] = r.forward_columns;
    j["backward_columns"] = r.backward_columns;
  }
  j["factor_s"] = r.factor_s();
  j["query_s"] = r.query_s;
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["timings"] = circle ? timings(in, {{"operator_s", r.operator_s}, {"order_s", r.order_s},
                                       {"analyze_s", r.analyze_s},   {"numeric_s", r.numeric_s},
                                       {"prepare_s", r.prepare_s},   {"grow_s", r.grow_s},
                                       {"system_s", r.system_s},     {"update_s", r.update_s},
                                       {"solve_s", r.solve_s},       {"check_s", r.check_s}})
                        : timings(in, {{"operator_s", r.operator_s}, {"order_s", r.order_s},
                                       {"analyze_s", r.analyze_s},   {"numeric_s", r.numeric_s},
                                       {"prepare_s", r.prepare_s},   {"grow_s", r.grow_s},
                                       {"rhs_s", r.rhs_s},           {"solve_s", r.solve_s},
                                       {"check_s", r.check_s}});
  return j;
}

}  // namespace

int run_param_patch(const CommonOptions& opt, const ParamRequest& q, const RunContext& ctx) {
  check_request(q);
  check_uv_output(opt, "param");
  const Input in = load_input(opt, ctx);
  const int32_t nv = in.mesh.num_vertices();
  if (q.center >= nv)
    fail(ErrorCode::BadInput, "--center " + std::to_string(q.center) + " is outside 0.." + std::to_string(nv - 1));
  const Session session{Mesh(in.mesh), session_options(in)};
  const ParamReport r = session.param(q, ctx);
  if (!opt.output.empty()) {
    WriteOptions wo;
    wo.uv = &r.uv;
    write_mesh(opt.output, r.patch, wo);
    log_written(opt.output);
  }
  const Json j = patch_json(opt, in, q, r);
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": patch of " << r.patch_vertices.size() << " vertices around " << q.center
       << " (boundary " << r.boundary_vertices;
    if (q.boundary == "circle")
      os << " vertices on a circle, " << r.holes_filled << " hole(s) filled";
    else
      os << " vertices, " << r.boundary_loops << " loop(s)";
    os << ", Euler characteristic " << r.euler_characteristic << ")\n  flipped faces " << r.flipped_faces
       << ", degenerate faces " << r.degenerate_faces << "\n  factor " << j["factor_s"] << " s, patch "
       << r.query_s << " s\n";
  });
  return 0;
}

}  // namespace locus::cli
