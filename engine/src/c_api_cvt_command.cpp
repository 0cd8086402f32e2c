// The C API of the cvt command (locus_commands.h, locus_cvt_options): the C
// options translated to the engine's request (engine/include/locus/engine/
// cvt_request.hpp), run by the Session, the labels, report and remesh handle
// copied out. Also the sites of a remesh handle.
#include <algorithm>
#include <cstring>
#include <memory>
#include <string>

#include "c_api_support.hpp"
#include "locus/engine/cvt_request.hpp"
#include "session_state.hpp"

using namespace locus::c_api_detail;

namespace {

locus::CvtRequest request_of(const locus_cvt_options& o) {
  locus::CvtRequest q;
  q.sites = o.sites;
  q.iters = o.iters;
  q.stop_energy = o.stop_energy;
  q.anisotropy = o.anisotropy;
  q.solver = text(o.solver, q.solver);
  q.t = text(o.t, q.t);
  q.save = text(o.save, "");
  q.load = text(o.load, "");
  q.no_refine = o.no_refine != 0;
  q.centroid_t = text(o.centroid_t, "");
  q.t_centroid = text(o.t_centroid, "");
  q.fit_rings = o.fit_rings;
  q.fit_sigma = o.fit_sigma;
  q.no_split = o.no_split != 0;
  q.labels = text(o.labels, "");
  q.sites_out = text(o.sites_out, "");
  q.repair_rounds = o.repair_rounds;
  q.refinements = o.refinements;
  q.optimize = o.optimize;
  q.no_hausdorff = o.no_hausdorff != 0;
  q.track_quality = o.track_quality != 0;
  q.seed = o.seed;
  return q;
}

void fill_report(const locus::CvtReport& r, locus_cvt_report& o) {
  std::memset(&o, 0, sizeof o);
  o.sites = static_cast<int64_t>(r.site_face.size());
  o.complete = r.complete ? 1 : 0;
  o.added_sites = r.added_sites, o.repair_rounds = r.repair_rounds, o.refinements = r.refinements;
  o.lloyd_iterations = r.lloyd_iterations;
  const locus::CvtMeshStats& st = r.remesh_stats;
  o.remesh.vertices = st.vertices, o.remesh.faces = st.faces;
  o.remesh.manifold = st.manifold && r.complete ? 1 : 0;
  o.remesh.genus = st.genus, o.remesh.components = st.components, o.remesh.boundary_loops = st.boundary_loops;
  o.remesh.mean_min_angle_deg = st.mean_min_angle_deg, o.remesh.min_angle_deg = st.min_angle_deg;
  o.remesh.pct_below_30_deg = st.pct_below_30_deg, o.remesh.hausdorff_rel = st.hausdorff_rel;
  o.remesh.added_sites = r.added_sites;
  o.h = r.h, o.t = r.t, o.t_centroid = r.t_centroid;
  o.dual_triangles = r.dual_triangles;
  o.min_angle_deg = r.cells_min_angle_deg, o.mean_angle_deg = r.cells_mean_angle_deg;
  o.area_cv = r.area_cv, o.area_variance = r.area_variance;
  o.area_cv_vertex = r.area_cv_vertex, o.area_variance_vertex = r.area_variance_vertex;
  o.empty_cells = r.empty_cells, o.unreached_vertices = r.unreached, o.fallback_faces = r.fallback_faces;
  o.flips = r.flips, o.smoothing_moves = r.smoothing_moves, o.boundary_moves = r.boundary_moves;
  o.requested = r.requested, o.delivered = r.delivered, o.repair_sites = r.repair_sites;
  o.removed_sites = r.removed_sites, o.density_passes = r.density_passes, o.geodesic_rounds = r.geodesic_rounds;
  const locus::CvtDefects& d = r.defects_left;
  o.defects_left = d.split_cells + d.non_disk_cells + d.split_interfaces + d.loop_interfaces +
                   d.boundary_interfaces + d.repeated_corners + d.split_boundary_runs + d.short_boundary_loops;
}

}  // namespace

extern "C" {

locus_cvt_options locus_cvt_options_default(void) {
  const locus::CvtRequest d;
  locus_cvt_options o;
  std::memset(&o, 0, sizeof o);  // strings NULL: the request's defaults
  o.sites = d.sites;
  o.iters = d.iters;
  o.stop_energy = d.stop_energy;
  o.anisotropy = d.anisotropy;
  o.no_refine = d.no_refine;
  o.fit_rings = d.fit_rings;
  o.fit_sigma = d.fit_sigma;
  o.no_split = d.no_split;
  o.repair_rounds = d.repair_rounds;
  o.refinements = d.refinements;
  o.optimize = d.optimize;
  o.no_hausdorff = d.no_hausdorff;
  o.track_quality = d.track_quality;
  o.seed = d.seed;
  return o;
}

locus_status locus_cvt_run(locus_session* session, const locus_cvt_options* options, int32_t* out_labels,
                           locus_cvt_report* out_report, locus_remesh** out_remesh, const locus_run_options* opts) {
  return guarded("locus_cvt_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    CallContext cc(opts);
    no_run_time(cc);
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
