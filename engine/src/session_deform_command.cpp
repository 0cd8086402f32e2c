// `deform` as every front end runs it (engine/include/locus/engine/
// deform_request.hpp): region-of-interest deformation with the factor-once
// submesh factor (thesis §5.1, §5.7; pipelines/.../deform/deform.hpp). The
// global operator is factored once — the Session's cached factor per energy
// at the default regularization, else the request's own (with its factor
// cache files); the factor of A_FF for the free vertices comes from the
// update kernel; the handle offset is then one 8-lane solve. With the
// baseline (the CLI's), the same A_FF is also ordered, analyzed and factored
// from scratch and solved again, and the largest coordinate difference of
// the two results reported.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "command_clock.hpp"
#include "field_copy.hpp"
#include "locus/engine/deform_request.hpp"
#include "locus/engine/factor_store.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"
#include "sheets_session.hpp"

namespace locus {

using namespace session_detail;

void check_request(const DeformCommandRequest& req) {
  parse_deform_energy(req.energy);
  if (req.roi_seed < 0) fail(ErrorCode::BadUsage, "roi_seed " + std::to_string(req.roi_seed) + " is not a vertex id");
  if (req.handle < 0) fail(ErrorCode::BadUsage, "handle " + std::to_string(req.handle) + " is not a vertex id");
  if (!(req.roi_fraction >= 0 && req.roi_fraction <= 1))
    fail(ErrorCode::BadUsage, "roi_fraction must be in [0, 1] (got " + format_number(req.roi_fraction) + ")");
  if (req.handle_ring < 0 || req.handle_ring > 1000)
    fail(ErrorCode::BadUsage, "handle_ring must be in 0..1000 (got " + std::to_string(req.handle_ring) + ")");
  for (double c : req.offset)
    if (!std::isfinite(c)) fail(ErrorCode::BadUsage, "the offset must be finite");
  if (!(req.regularization > 0) || !std::isfinite(req.regularization))
    fail(ErrorCode::BadUsage, "--regularization must be a positive number");
  check_factor_cache_files({req.save, req.load});
}

namespace session_detail {
namespace {

constexpr double kDefaultRegularization = 1e-6;  // the Session's cached operators' (prepare_deform_operator)

using command_clock::seconds;

// The global operator: the Session's cached one, or the request's own through the factor cache.
std::shared_ptr<const DeformOperator> global_operator(State& s, const DeformCommandRequest& req, DeformEnergy energy,
                                                      const CallProgress& progress, DeformCommandReport& r) {
  const FactorCacheFiles files{req.save, req.load};
  if (!files.used() && req.regularization == kDefaultRegularization)
    return s.deform_ops.get(static_cast<int>(energy), progress.build(), [&] {
      auto o = std::make_shared<const DeformOperator>(
          prepare_deform_operator(s.mesh, energy, kDefaultRegularization, progress.build()));
      s.counters->deform.fetch_add(1);
      return o;
    });
  auto op = std::make_shared<DeformOperator>();
  op->energy = energy;
  const auto t0 = std::chrono::steady_clock::now();
  op->mats = deform_matrices(s.mesh, energy, req.regularization);
  op->operator_s = seconds(t0);
  progress.build().check_cancel();
  // The label carries the energy; t holds the relative regularization (it changes the matrix).
  const FactorRequest freq{std::string("deform-") + deform_energy_name(energy), req.regularization, &op->mats.A};
  Factors global = factor_or_load(files, s.mesh, std::span(&freq, 1), progress.build());
  op->L = std::move(global.factors[0]);
  op->order_s = global.order_s;
  op->analyze_s = global.analyze_s;
  op->factor_s = global.numeric_s;
  r.factor_cache = FactorCacheReport{req.load, req.save, global.load_s, global.save_s};
  return op;
}

// The baseline: A_FF ordered, analyzed and factored from scratch, the same solve.
void compare_refactor(const DeformSystem& sys, const Mesh& mesh, const Mesh& target, const Mesh& out,
                      const RunContext& ctx, DeformCommandReport& r) {
  const CscMatrix& Aff = sys.sub.A_sub;
  auto t0 = std::chrono::steady_clock::now();
  const Ordering ord = order_matrix(Aff);
  auto S = analyze(Aff, ord);
  r.values_stored_refactor = S->nnz_L;
  const NumericFactor Fs = factorize(S, Aff, ctx);
  r.refactor_s = seconds(t0);
  ctx.check_cancel();
  Mesh out_ref;
  t0 = std::chrono::steady_clock::now();
  solve_deformation(Fs, sys, mesh, target, out_ref);
  r.refactor_solve_s = seconds(t0);
  for (int32_t v = 0; v < mesh.num_vertices(); ++v)
    r.update_vs_refactor_max_diff =
        std::max({r.update_vs_refactor_max_diff, std::abs(out.x[v] - out_ref.x[v]), std::abs(out.y[v] - out_ref.y[v]),
                  std::abs(out.z[v] - out_ref.z[v])});
  r.compared = true;
}

void copy_result(const Mesh& mesh, const Mesh& out, DeformCommandReport& r) {
  const int32_t n = mesh.num_vertices();
  r.xyz.resize(3 * static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) {
    r.xyz[3 * static_cast<size_t>(v)] = out.x[v];
    r.xyz[3 * static_cast<size_t>(v) + 1] = out.y[v];
    r.xyz[3 * static_cast<size_t>(v) + 2] = out.z[v];
    const double dx = out.x[v] - mesh.x[v], dy = out.y[v] - mesh.y[v], dz = out.z[v] - mesh.z[v];
    r.max_displacement = std::max(r.max_displacement, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
}

// A mesh that is not a manifold: the deformation of its manifold sheets
// (sheets_session.hpp); a vertex split into copies moves to their mean, an
// unreferenced vertex stays where it is.
DeformCommandReport sheets_deform(State& s, const DeformCommandRequest& req, const RunContext& ctx, bool compare) {
  const std::shared_ptr<const SheetsSession> sh = sheets_session(s, ctx);
  const std::string name = mesh_name(s.mesh);
  DeformCommandRequest q = req;
  q.roi_seed = sheet_vertex(*sh, req.roi_seed, "roi_seed", name);
  q.handle = sheet_vertex(*sh, req.handle, "handle", name);
  DeformCommandReport r = sh->session->deform(q, ctx, compare);
  const int32_t n = s.mesh.num_vertices();
  std::vector<double> xyz(3 * static_cast<size_t>(n), 0.0), copies(static_cast<size_t>(n), 0.0);
  for (size_t c = 0; c < sh->sheets.vertex_of.size(); ++c) {
    const int32_t v = sh->sheets.vertex_of[c];
    for (int d = 0; d < 3; ++d) xyz[3 * v + d] += r.xyz[3 * c + d];
    copies[v] += 1;
  }
  double moved = 0;
  for (int32_t v = 0; v < n; ++v) {
    const double p[3] = {s.mesh.x[v], s.mesh.y[v], s.mesh.z[v]};
    double d2 = 0;
    for (int d = 0; d < 3; ++d) {
      xyz[3 * v + d] = copies[v] > 0 ? xyz[3 * v + d] / copies[v] : p[d];
      d2 += (xyz[3 * v + d] - p[d]) * (xyz[3 * v + d] - p[d]);
    }
    moved = std::max(moved, std::sqrt(d2));
  }
  r.xyz = std::move(xyz);
  r.n = n;
  r.max_displacement = moved;
  r.warnings.push_back(sh->describe("deform", name));
  return r;
}

}  // namespace
}  // namespace session_detail

DeformCommandReport Session::deform(const DeformCommandRequest& req, const RunContext& ctx,
                                    bool compare_with_refactor) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, req.roi_seed, "roi_seed");
  check_vertex(*s, req.handle, "handle");
  if (impl_->op.robust && impl_->op.any_defect()) return sheets_deform(*s, req, ctx, compare_with_refactor);
  const DeformEnergy energy = parse_deform_energy(req.energy);
  DeformCommandReport r;
  r.energy = deform_energy_name(energy);
  r.n = impl_->nv;
  const CallProgress progress(ctx, req.save.size() + req.load.size() > 0 ||
                                       req.regularization != kDefaultRegularization ||
                                       !s->deform_ops.contains(static_cast<int>(energy)));
  const auto op = global_operator(*s, req, energy, progress, r);
  r.operator_s = op->operator_s, r.order_s = op->order_s, r.analyze_s = op->analyze_s, r.factor_s = op->factor_s;
  ctx.check_cancel();
  auto t0 = std::chrono::steady_clock::now();
  const DeformRegion region = make_deform_region(s->derived->adjacency, static_cast<int32_t>(req.roi_seed),
                                                 req.roi_fraction, static_cast<int32_t>(req.handle), req.handle_ring);
  r.region_s = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  const DeformSystem sys = prepare_deform_system(*op, region, progress.query());
  r.system_s = seconds(t0);  // update + E_FF + coupling to the known vertices
  r.update_s = sys.update_s;
  ctx.check_cancel();
  const Mesh target = handle_target(s->mesh, region, req.offset);
  Mesh out;
  t0 = std::chrono::steady_clock::now();
  const DeformSolveStats st = solve_deformation(sys.sub.factor, sys, s->mesh, target, out);
  r.solve_s = seconds(t0);
  ctx.check_cancel();
  if (compare_with_refactor) compare_refactor(sys, s->mesh, target, out, ctx, r);
  copy_result(s->mesh, out, r);
  const FactorUpdateStats& us = sys.sub.stats;
  r.roi_vertices = static_cast<int32_t>(region.roi.size());
  r.handle_vertices = static_cast<int32_t>(region.handle.size());
  r.free_vertices = static_cast<int32_t>(region.free.size());
  LOCUS_COPY_FIELDS(r, us, columns_updated_fraction, supernodes_recomputed, supernodes);
  r.values_stored_update = us.values_stored;
  r.update_structure_s = us.structure_s, r.update_mark_s = us.mark_s, r.update_copy_s = us.copy_s;
  r.update_factor_s = us.factor_s;
  r.refinement_steps = st.refinement_steps;
  r.residual = st.residual;
  progress.finish("deform");
  return r;
}

}  // namespace locus
