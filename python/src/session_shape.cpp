// locus.Session: shape pipelines — region-of-interest deformation with the
// factor-once submesh update (thesis ch. 5), disk and patch parameterizations
// (§2.6, §4.4), perfect Laplacians (ch. 2, Algorithm 1) and self-supporting
// surfaces (§2.6, eq. 2.12).
#include <string>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {

DiskParamMethod disk_param_method(const std::string& name) {
  if (name == "perfect") return DiskParamMethod::Perfect;
  if (name == "cotan") return DiskParamMethod::Cotan;
  if (name == "uniform") return DiskParamMethod::Uniform;
  usage_error("method must be 'perfect', 'cotan' or 'uniform', got '" + name + "'");
}

py::object disk_param_result(DiskParamResult&& r) {
  const auto n = static_cast<py::ssize_t>(r.uv.size() / 2);
  return result(py::dict("uv"_a = take(std::move(r.uv), {n, 2}), "flipped_faces"_a = r.flipped_faces,
                         "degenerate_faces"_a = r.degenerate_faces, "negative_weights"_a = r.negative_weights,
                         "converged"_a = r.converged, "iterations"_a = r.iterations));
}

py::object perfect_laplacian_result(PerfectLaplacianOutput&& r) {
  const auto ne = static_cast<py::ssize_t>(r.weights.size());
  const auto nv = static_cast<py::ssize_t>(r.xyz.size() / 3);
  return result(py::dict("edges"_a = take(std::move(r.edges), {ne, 2}), "weights"_a = take(std::move(r.weights)),
                         "V"_a = take(std::move(r.xyz), {nv, 3}), "converged"_a = r.converged,
                         "iterations"_a = r.iterations, "max_displacement_rel"_a = r.max_displacement_rel,
                         "mean_displacement_rel"_a = r.mean_displacement_rel));
}

py::object self_support_result(SelfSupportOutput&& r) {
  const auto ne = static_cast<py::ssize_t>(r.forces.size());
  const auto nv = static_cast<py::ssize_t>(r.xyz.size() / 3);
  return result(py::dict("edges"_a = take(std::move(r.edges), {ne, 2}), "forces"_a = take(std::move(r.forces)),
                         "V"_a = take(std::move(r.xyz), {nv, 3}), "converged"_a = r.converged,
                         "iterations"_a = r.iterations, "residual_rel"_a = r.residual_rel));
}

namespace {

// Session.deform: the `deform` command (engine/include/locus/engine/deform_request.hpp) with every option
// of the CLI, without the CLI's from-scratch baseline.
py::object deform(const Session& s, int64_t roi_seed, int64_t handle, const py::handle& offset, double roi_fraction,
                  int32_t handle_ring, const std::string& energy, double regularization, const py::handle& save,
                  const py::handle& load, int threads, py::object progress) {
  DeformCommandRequest req;
  req.roi_seed = roi_seed;
  req.roi_fraction = roi_fraction;
  req.handle = handle;
  req.handle_ring = handle_ring;
  std::vector<double> d;
  for (const py::handle x : py::module_::import("numpy").attr("asarray")(offset, "dtype"_a = "float64").attr("ravel")())
    d.push_back(x.cast<double>());
  if (d.size() != 3) usage_error("offset must be 3 numbers (dx, dy, dz), got " + std::to_string(d.size()));
  req.offset = {d[0], d[1], d[2]};
  req.energy = energy;
  req.regularization = regularization;
  req.save = optional_text(save);
  req.load = optional_text(load);
  DeformCommandReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.deform(req, ctx); });
  const auto nv = static_cast<py::ssize_t>(r.xyz.size() / 3);
  py::dict out("V"_a = take(std::move(r.xyz), {nv, 3}), "roi_size"_a = r.roi_vertices, "free_size"_a = r.free_vertices,
               "handle_vertices"_a = r.handle_vertices, "columns_updated_fraction"_a = r.columns_updated_fraction,
               "refinement_steps"_a = r.refinement_steps, "residual"_a = r.residual,
               "max_displacement"_a = r.max_displacement, "energy"_a = r.energy);
  out["supernodes_recomputed"] = r.supernodes_recomputed;
  out["supernodes"] = r.supernodes;
  out["values_stored_update"] = r.values_stored_update;
  out["update_s"] = r.update_s;
  out["solve_s"] = r.solve_s;
  out["global_factor_s"] = r.order_s + r.analyze_s + r.factor_s;
  out["factor_cache"] = r.factor_cache.used()
                            ? py::object(py::dict("loaded"_a = r.factor_cache.loaded, "saved"_a = r.factor_cache.saved,
                                                  "load_s"_a = r.factor_cache.load_s, "save_s"_a = r.factor_cache.save_s))
                            : py::object(py::none());
  if (!r.warnings.empty()) {
    py::list w;
    for (const std::string& text : r.warnings) w.append(text);
    out["warnings"] = w;
  }
  return result(out);
}

py::object patch_param(const Session& s, int32_t center, double fraction, const std::string& boundary, int threads,
                       py::object progress) {
  PatchParamRequest req;
  req.center = center;
  req.fraction = fraction;
  if (boundary == "neumann") req.boundary = PatchBoundary::Neumann;
  else if (boundary == "circle") req.boundary = PatchBoundary::Circle;
  else usage_error("boundary must be 'neumann' or 'circle', got '" + boundary + "'");
  PatchParamResult r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.parameterize_patch(req, ctx); });
  const auto n = static_cast<py::ssize_t>(r.vertices.size());
  const auto nf = static_cast<py::ssize_t>(r.triangles.size() / 3);
  return result(py::dict("vertices"_a = take(std::move(r.vertices)), "F"_a = take(std::move(r.triangles), {nf, 3}),
                         "uv"_a = take(std::move(r.uv), {n, 2}), "boundary_vertices"_a = r.boundary_vertices,
                         "flipped_faces"_a = r.flipped_faces, "degenerate_faces"_a = r.degenerate_faces,
                         "holes_filled"_a = r.holes_filled));
}

}  // namespace

void bind_session_shape(SessionClass& cls) {
  const DeformCommandRequest dq;
  cls.def("deform", &deform, "roi_seed"_a, "handle"_a, "offset"_a, py::kw_only(), "roi_fraction"_a = dq.roi_fraction,
          "handle_ring"_a = dq.handle_ring, "energy"_a = dq.energy, "regularization"_a = dq.regularization,
          "save"_a = py::none(), "load"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
          (std::string("deform(roi_seed, handle, offset, *, roi_fraction=" + py_literal(dq.roi_fraction) + ", handle_ring=" + py_literal(dq.handle_ring) + ", energy=" + py_literal(dq.energy) + ", regularization=" + py_literal(dq.regularization) + ", save=None, load=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus deform` with every option: region-of-interest deformation (thesis ch. 5) on a copy of "
                       "the positions: the ROI is the breadth-first patch of round(roi_fraction * nv) vertices "
                       "around roi_seed; the handle (vertex `handle` and its handle_ring-ring inside the ROI) moves "
                       "by offset (dx, dy, dz, units of the positions); outside the ROI nothing moves. energy: "
                       "'laplacian' or 'bilaplacian'. regularization: relative eps of the factored global operator "
                       "(the Session keeps that factor at the default 1e-6). save / load: a factor cache file of "
                       "the global factor.\n"
                       "Returns .V ((nv, 3) deformed positions), .roi_size, .free_size, "
                       ".columns_updated_fraction, .refinement_steps, .residual, .max_displacement and the "
                       "update's statistics.\n") + kCallArgs).c_str());
  cls.def(
      "parameterize_disk",
      [](const Session& s, const std::string& method, int32_t max_iterations, double eps, int threads,
         py::object progress) {
        DiskParamRequest req{disk_param_method(method), max_iterations, eps};
        DiskParamResult r;
        run({threads, progress}, [&](const RunContext& ctx) { r = s.parameterize_disk(req, ctx); });
        return disk_param_result(std::move(r));
      },
      py::kw_only(), "method"_a = "perfect", "max_iterations"_a = 1000, "eps"_a = 1e-6, "threads"_a = 0,
      "progress"_a = py::none(),
      (std::string("parameterize_disk(*, method='perfect', max_iterations=1000, eps=1e-6, threads=0, progress=None)\n\n"
                   "Flip-free parameterization of a disk-like mesh (thesis §2.6): boundary on the unit circle by arc "
                   "length, interior by perfect (Algorithm 1), cotan or uniform weights. Returns .uv ((nv, 2)), "
                   ".flipped_faces, .degenerate_faces, .negative_weights, .converged, .iterations.\n") +
       kCallArgs).c_str());
  cls.def("parameterize_patch", &patch_param, "center"_a, "fraction"_a = 0.1, py::kw_only(), "boundary"_a = "neumann",
          "threads"_a = 0, "progress"_a = py::none(),
          (std::string("parameterize_patch(center, fraction=0.1, *, boundary='neumann', threads=0, progress=None)\n\n"
                       "Harmonic parameterization (thesis §4.4) of the breadth-first patch of round(fraction * nv) "
                       "vertices around center, from the global factor of -L + eps M: boundary 'neumann' (eq. 4.6) "
                       "or 'circle'. Returns .vertices (global ids, center first), .F ((m, 3) into .vertices), .uv "
                       "((n, 2) in the unit disk), .boundary_vertices, .flipped_faces, .degenerate_faces, "
                       ".holes_filled.\n") + kCallArgs).c_str());
  cls.def(
      "self_supporting",
      [](const Session& s, double load_density, int32_t max_iterations, double eps, int threads, py::object progress) {
        SelfSupportRequest req{load_density, max_iterations, eps};
        SelfSupportOutput r;
        run({threads, progress}, [&](const RunContext& ctx) { r = s.self_supporting(req, ctx); });
        return self_support_result(std::move(r));
      },
      py::kw_only(), "load_density"_a = 1.0, "max_iterations"_a = 1000, "eps"_a = 1e-6, "threads"_a = 0,
      "progress"_a = py::none(),
      (std::string("self_supporting(*, load_density=1.0, max_iterations=1000, eps=1e-6, threads=0, progress=None)\n\n"
                   "Self-supporting surface (thesis §2.6, eq. 2.12), supports on the boundary: .edges, .forces "
                   "(per edge, >= 0, load units), .V (the equilibrium surface), .converged, .iterations, "
                   ".residual_rel.\n") + kCallArgs).c_str());
}

}  // namespace locus::python
