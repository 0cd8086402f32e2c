// locus.Session.cvt_command: the `cvt` command with every option of the CLI,
// as keyword arguments of the same names and defaults (engine/include/locus/
// engine/cvt_request.hpp), returning the cells, the sites, the remesh and
// the statistics the CLI reports. Session.cvt (sites, iterations, seed on the
// Session's kept operator) stays the cached tier.
#include <string>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "locus/engine/cvt_request.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

py::dict defects_dict(const CvtDefects& d) {
  return py::dict("split_cells"_a = d.split_cells, "non_disk_cells"_a = d.non_disk_cells,
                  "split_interfaces"_a = d.split_interfaces, "loop_interfaces"_a = d.loop_interfaces,
                  "boundary_interfaces"_a = d.boundary_interfaces, "repeated_corners"_a = d.repeated_corners,
                  "split_boundary_runs"_a = d.split_boundary_runs, "short_boundary_loops"_a = d.short_boundary_loops);
}

// The `remesh` object of `locus cvt --json`, its input's topology included.
py::dict remesh_dict(const CvtReport& r, double features) {
  const CvtMeshStats& st = r.remesh_stats;
  py::dict d("vertices"_a = st.vertices, "faces"_a = st.faces, "manifold"_a = st.manifold && r.complete,
             "genus"_a = st.genus, "components"_a = st.components, "boundary_loops"_a = st.boundary_loops,
             "mean_min_angle_deg"_a = st.mean_min_angle_deg, "min_angle_deg"_a = st.min_angle_deg,
             "pct_below_30_deg"_a = st.pct_below_30_deg, "hausdorff_rel"_a = st.hausdorff_rel,
             "added_sites"_a = r.added_sites);
  d["dual_mean_min_angle_deg"] = r.dual_mean_min_angle_deg;
  d["dual_min_angle_deg"] = r.dual_min_angle_deg;
  d["flips"] = r.flips;
  d["smoothing_moves"] = r.smoothing_moves;
  d["boundary_moves"] = r.boundary_moves;
  d["repair_rounds"] = r.repair_rounds;
  d["refinements"] = r.refinements;
  d["lloyd_iterations"] = r.lloyd_iterations;
  d["requested"] = r.requested;
  d["delivered"] = r.delivered;
  d["repair_sites"] = r.repair_sites;
  d["removed_sites"] = r.removed_sites;
  d["density_passes"] = r.density_passes;
  d["geodesic_rounds"] = r.geodesic_rounds;
  d["rebalance_rounds"] = r.rebalance_rounds;
  d["single_triangles"] = r.single_triangles;
  if (features > 0)
    d["features"] = py::dict("angle_deg"_a = features, "edges"_a = r.feature_edges, "curves"_a = r.feature_curves,
                             "corners"_a = r.feature_corners, "sites"_a = r.feature_sites);
  d["defects_before_repair"] = defects_dict(r.defects_before_repair);
  d["defects_left"] = defects_dict(r.defects_left);
  d["input"] = py::dict("genus"_a = r.input_stats.genus, "components"_a = r.input_stats.components,
                        "boundary_loops"_a = r.input_stats.boundary_loops);
  if (r.sheets.cut) {  // remeshed as the manifold sheets of a mesh that is not a manifold
    const CvtSheets& c = r.sheets;
    d["sheets"] = py::dict("split_vertices"_a = c.split_vertices, "cut_edges"_a = c.cut_edges,
                           "flipped_faces"_a = c.flipped_faces, "dropped_faces"_a = c.dropped_faces,
                           "split_faces"_a = c.split_faces, "unreferenced_vertices"_a = c.unreferenced_vertices);
  }
  return d;
}

py::object report_object(CvtReport&& r, double features) {
  const auto ns = static_cast<py::ssize_t>(r.site_face.size());
  std::vector<double> xyz;
  for (int32_t v = 0; v < r.remesh.num_vertices(); ++v) xyz.insert(xyz.end(), {r.remesh.x[v], r.remesh.y[v], r.remesh.z[v]});
  const auto nrv = static_cast<py::ssize_t>(r.remesh.num_vertices());
  const auto nrf = static_cast<py::ssize_t>(r.remesh.face_vertices.size() / 3);
  std::vector<int32_t> tris(r.remesh.face_vertices.begin(), r.remesh.face_vertices.end());
  py::dict d("labels"_a = take(std::move(r.label)), "sites"_a = take(std::move(r.site_xyz), {ns, 3}),
             "site_face"_a = take(std::move(r.site_face)), "site_vertex"_a = take(std::move(r.site_vertex)),
             "site_bary"_a = take(std::move(r.site_bary), {ns, 3}), "complete"_a = r.complete,
             "remesh_V"_a = take(std::move(xyz), {nrv, 3}), "remesh_F"_a = take(std::move(tris), {nrf, 3}),
             "remesh_site"_a = take(std::move(r.remesh_site)), "remesh"_a = remesh_dict(r, features));
  d["n"] = r.n;
  d["h"] = r.h;
  d["t"] = r.t;
  d["t_centroid"] = r.t_centroid;
  d["factor_mb"] = static_cast<double>(r.factor_bytes) / 1e6;
  d["mean_kept_fraction"] = r.mean_kept_fraction;
  d["dual_triangles"] = r.dual_triangles;
  d["min_angle_deg"] = r.cells_min_angle_deg;
  d["mean_angle_deg"] = r.cells_mean_angle_deg;
  d["min_angle_sites"] = py::cast(std::vector<int32_t>(r.min_angle_sites.begin(), r.min_angle_sites.end()));
  d["angle_histogram_5deg"] = py::cast(std::vector<int64_t>(r.angle_histogram.begin(), r.angle_histogram.end()));
  d["cell_area"] = take(std::move(r.cell_area));
  d["area_cv"] = r.area_cv;
  d["area_variance"] = r.area_variance;
  d["area_cv_vertex"] = r.area_cv_vertex;
  d["area_variance_vertex"] = r.area_variance_vertex;
  d["fallback_faces"] = r.fallback_faces;
  d["empty_cells"] = r.empty_cells;
  d["unreached_vertices"] = r.unreached;
  d["energy"] = py::cast(r.energy);
  d["moved_h"] = py::cast(r.moved);
  d["centroid_bias_h"] = py::cast(r.centroid_bias);
  d["centroid_bias_median_h"] = py::cast(r.centroid_bias_median);
  d["mean_angle_all"] = py::cast(r.mean_angle);
  d["min_angle_all"] = py::cast(r.min_angle);
  d["factor_cache"] = py::dict("loaded"_a = r.factor_cache.loaded.empty() ? py::object(py::none()) : py::str(r.factor_cache.loaded),
                               "saved"_a = r.factor_cache.saved.empty() ? py::object(py::none()) : py::str(r.factor_cache.saved));
  d["timings"] = py::dict("factor_s"_a = r.prepare_s + r.remesh_factor_s, "lloyd_s"_a = r.lloyd_s,
                          "repair_s"_a = r.repair_s, "dual_s"_a = r.dual_s, "optimize_s"_a = r.optimize_s,
                          "stats_s"_a = r.stats_s);
  return result(d);
}

py::object cvt_command(const Session& s, int32_t sites, int32_t iters, double stop_energy, double anisotropy,
                       const std::string& solver, const std::string& t, const py::handle& save, const py::handle& load,
                       bool no_refine, const py::handle& centroid_t, const py::handle& t_centroid, int32_t fit_rings,
                       double fit_sigma, bool no_split, const py::handle& labels, const py::handle& sites_out,
                       int32_t repair_rounds, int32_t refinements, int32_t optimize, double features,
                       bool no_hausdorff, bool track_quality, uint64_t seed, int threads, py::object progress) {
  CvtRequest q;
  q.sites = sites, q.iters = iters, q.stop_energy = stop_energy, q.anisotropy = anisotropy;
  q.solver = solver, q.t = t, q.save = optional_text(save), q.load = optional_text(load), q.no_refine = no_refine;
  q.centroid_t = optional_text(centroid_t), q.t_centroid = optional_text(t_centroid);
  q.fit_rings = fit_rings, q.fit_sigma = fit_sigma, q.no_split = no_split;
  q.labels = optional_text(labels), q.sites_out = optional_text(sites_out);
  q.repair_rounds = repair_rounds, q.refinements = refinements, q.optimize = optimize, q.features = features;
  q.no_hausdorff = no_hausdorff, q.track_quality = track_quality, q.seed = seed;
  CvtReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.cvt(q, ctx); });
  return report_object(std::move(r), q.features);
}

}  // namespace

void bind_session_cvt_command(SessionClass& cls) {
  const CvtRequest d;
  const std::string signature =
      "cvt_command(sites=" + py_literal(d.sites) + ", iters=" + py_literal(d.iters) +
      ", *, stop_energy=" + py_literal(d.stop_energy) + ", anisotropy=" + py_literal(d.anisotropy) +
      ", solver=" + py_literal(d.solver) + ", t=" + py_literal(d.t) + ", save=None, load=None, no_refine=" +
      py_literal(d.no_refine) + ", centroid_t=None, t_centroid=None, fit_rings=" + py_literal(d.fit_rings) +
      ", fit_sigma=" + py_literal(d.fit_sigma) + ", no_split=" + py_literal(d.no_split) +
      ", labels=None, sites_out=None, repair_rounds=" + py_literal(d.repair_rounds) +
      ", refinements=" + py_literal(d.refinements) + ", optimize=" + py_literal(d.optimize) +
      ", features=" + py_literal(d.features) +
      ", no_hausdorff=" + py_literal(d.no_hausdorff) + ", track_quality=" + py_literal(d.track_quality) +
      ", seed=" + py_literal(d.seed) + ", threads=0, progress=None) -> namespace\n\n";
  cls.def("cvt_command", &cvt_command, "sites"_a = d.sites, "iters"_a = d.iters, py::kw_only(),
          "stop_energy"_a = d.stop_energy, "anisotropy"_a = d.anisotropy, "solver"_a = d.solver, "t"_a = d.t,
          "save"_a = py::none(), "load"_a = py::none(), "no_refine"_a = d.no_refine, "centroid_t"_a = py::none(),
          "t_centroid"_a = py::none(), "fit_rings"_a = d.fit_rings, "fit_sigma"_a = d.fit_sigma,
          "no_split"_a = d.no_split, "labels"_a = py::none(), "sites_out"_a = py::none(),
          "repair_rounds"_a = d.repair_rounds, "refinements"_a = d.refinements, "optimize"_a = d.optimize,
          "features"_a = d.features, "no_hausdorff"_a = d.no_hausdorff, "track_quality"_a = d.track_quality, "seed"_a = d.seed,
          "threads"_a = 0, "progress"_a = py::none(),
          (signature +
           "`locus cvt` with every option: `sites` seeded random initial sites (seed), `iters` Lloyd iterations "
           "with heat cells and centroids (thesis §3.7.1; stop_energy stops early), solver 'local' (approximate "
           "selective solves) or 'full', anisotropy: lambda of the R^6 lift (0: isotropic); t: the cells' "
           "diffusion time as the CLI's --t ('4h2': a multiple of h^2; or absolute), centroid_t the centroids' "
           "(None: t; t_centroid C is its deprecated spelling, Ch2); no_refine, fit_rings, fit_sigma: the "
           "centroid's fit; no_split: cell sources from vertex labels only; repair_rounds, refinements, optimize: "
           "the remesh's repair and optimization; features: a dihedral angle in degrees (0 <= DEG < 180; 0: "
           "none): input edges sharper than it stay remesh edges, their corners remesh vertices (.remesh['features'] "
           "counts them); no_hausdorff: skip the remesh's Hausdorff distance; "
           "track_quality: .mean_angle_all / .min_angle_all per iteration; save / load: a factor cache file of "
           "the cells' operator (isotropic); labels / sites_out: files to write (.ply, .obj, .off). Returns "
           ".labels (per vertex, its site), .sites (k, 3) with .site_face, .site_vertex, .site_bary, .complete, "
           ".remesh_V (n, 3), .remesh_F (m, 3), .remesh_site (empty without a complete remesh), .remesh (the "
           "CLI's `remesh` object) and the CLI's statistics.\n" +
           kCallArgs)
              .c_str());
}

}  // namespace locus::python
