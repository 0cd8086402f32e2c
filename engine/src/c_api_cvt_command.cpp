// The C API of the cvt command (locus_commands.h, locus_cvt_options): the C
// options translated to the engine's request (engine/include/locus/engine/
// cvt_request.hpp), run by the Session, the labels, report and remesh handle
// copied out. Also the sites of a remesh handle.
#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/cvt_request.hpp"
#include "session_state.hpp"

using namespace locus::c_api_detail;

// The cvt command's numeric options (its strings are NULL in the C defaults).
#define LOCUS_CVT_NUMBERS                                                                                        \
  sites, iters, stop_energy, anisotropy, no_refine, fit_rings, fit_sigma, no_split, repair_rounds, refinements, \
      optimize, no_hausdorff, track_quality, seed, features

namespace {

locus::CvtRequest request_of(const locus_cvt_options& o) {
  locus::CvtRequest q;
  LOCUS_COPY_FIELDS(q, o, LOCUS_CVT_NUMBERS, solver, t, save, load, centroid_t, t_centroid, labels, sites_out);
  return q;
}

void fill_report(const locus::CvtReport& r, locus_cvt_report& o) {
  std::memset(&o, 0, sizeof o);
  o.sites = static_cast<int64_t>(r.site_face.size());
  LOCUS_COPY_FIELDS(o, r, complete, added_sites, repair_rounds, refinements, lloyd_iterations, h, t, t_centroid,
                    dual_triangles, area_cv, area_variance, area_cv_vertex, area_variance_vertex, empty_cells,
                    fallback_faces, flips, smoothing_moves, boundary_moves, requested, delivered, repair_sites,
                    removed_sites, density_passes, geodesic_rounds, feature_edges, feature_curves, feature_corners,
                    feature_sites, rebalance_rounds, single_triangles);
  LOCUS_COPY_FIELDS(o.remesh, r.remesh_stats, vertices, faces, genus, components, boundary_loops, mean_min_angle_deg,
                    min_angle_deg, pct_below_30_deg, hausdorff_rel);
  o.remesh.manifold = r.remesh_stats.manifold && r.complete ? 1 : 0;
  o.remesh.added_sites = r.added_sites;
  o.min_angle_deg = r.cells_min_angle_deg, o.mean_angle_deg = r.cells_mean_angle_deg;
  o.unreached_vertices = r.unreached;
  const locus::CvtDefects& d = r.defects_left;
  o.defects_left = d.split_cells + d.non_disk_cells + d.split_interfaces + d.loop_interfaces +
                   d.boundary_interfaces + d.repeated_corners + d.split_boundary_runs + d.short_boundary_loops;
}

}  // namespace

extern "C" {

locus_cvt_options locus_cvt_options_default(void) {
  // strings NULL: the request's defaults
  return LOCUS_C_DEFAULTS(locus_cvt_options, locus::CvtRequest, LOCUS_CVT_NUMBERS);
}

locus_status locus_cvt_run(locus_session* session, const locus_cvt_options* options, int32_t* out_labels,
                           locus_cvt_report* out_report, locus_remesh** out_remesh, const locus_run_options* opts) {
  return command_run("locus_cvt_run", session, options, {}, opts, [&](locus::Session& s, CallContext& cc) {
    locus::CvtReport r = s.cvt(request_of(*options), cc.ctx);
    if (out_labels) std::copy(r.label.begin(), r.label.end(), out_labels);
    if (out_report) fill_report(r, *out_report);
    if (out_remesh) {
      auto h = std::make_unique<locus_remesh>();
      h->r = locus::cvt_result_of(std::move(r));
      *out_remesh = h.release();
    }
  });
}

int64_t locus_remesh_num_sites(const locus_remesh* remesh) {
  return remesh ? static_cast<int64_t>(remesh->r.site_face.size()) : 0;
}

locus_status locus_remesh_get_sites(const locus_remesh* remesh, double* out_xyz) {
  return guarded("locus_remesh_get_sites", [&] {
    require(remesh != nullptr, "remesh is NULL");
    require(out_xyz != nullptr, "out_xyz is NULL");
    std::copy(remesh->r.site_xyz.begin(), remesh->r.site_xyz.end(), out_xyz);
  });
}

}  // extern "C"
