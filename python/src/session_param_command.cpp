// locus.Session.param: the `param` command with every option of the CLI, as
// keyword arguments of the same names and defaults (engine/include/locus/
// engine/param_request.hpp). Session.parameterize_disk / parameterize_patch
// stay the cached tier.
#include <string>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

py::object param(const Session& s, const std::string& method, int32_t iters, double eps, int64_t center,
                 double fraction, const std::string& boundary, const py::handle& save, const py::handle& load,
                 int threads, py::object progress) {
  ParamRequest q;
  q.method = method;
  q.iters = iters;
  q.eps = eps;
  q.center = center;
  q.fraction = fraction;
  q.boundary = boundary;
  q.save = optional_text(save);
  q.load = optional_text(load);
  ParamReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.param(q, ctx); });
  const auto n = static_cast<py::ssize_t>(r.uv.size() / 2);
  py::dict d("domain"_a = r.domain, "uv"_a = take(std::move(r.uv), {n, 2}), "flipped_faces"_a = r.flipped_faces,
             "degenerate_faces"_a = r.degenerate_faces);
  if (r.domain == "disk") {
    d["first_flipped_face"] = r.first_flipped_face;
    d["min_corner_sin"] = r.min_corner_sin;
    d["negative_weights"] = r.negative_weights;
    d["min_weight"] = r.min_weight;
    d["converged"] = r.converged;
    d["iterations"] = r.iterations;
    d["zero_weights"] = r.zero_weights;
    d["param_s"] = r.param_s;
    return result(d);
  }
  std::vector<int32_t> tri(r.patch.f0.size() * 3);
  for (size_t f = 0; f < r.patch.f0.size(); ++f)
    tri[3 * f] = r.patch.f0[f], tri[3 * f + 1] = r.patch.f1[f], tri[3 * f + 2] = r.patch.f2[f];
  const auto nf = static_cast<py::ssize_t>(r.patch.f0.size());
  d["vertices"] = take(std::move(r.patch_vertices));
  d["F"] = take(std::move(tri), {nf, 3});
  d["boundary_vertices"] = r.boundary_vertices;
  d["boundary_loops"] = r.boundary_loops;
  d["euler_characteristic"] = r.euler_characteristic;
  d["holes_filled"] = r.holes_filled;
  d["orientation"] = r.orientation;
  d["etree_height"] = r.etree_height;
  d["factor_s"] = r.factor_s();
  d["query_s"] = r.query_s;
  return result(d);
}

}  // namespace

void bind_session_param_command(SessionClass& cls) {
  const ParamRequest d;
  cls.def("param", &param, "method"_a = d.method, py::kw_only(), "iters"_a = d.iters, "eps"_a = d.eps,
          "center"_a = d.center, "fraction"_a = d.fraction, "boundary"_a = d.boundary, "save"_a = py::none(),
          "load"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
          (std::string("param(method=" + py_literal(d.method) + ", *, iters=" + py_literal(d.iters) + ", eps=" + py_literal(d.eps) + ", center=" + py_literal(d.center) + ", fraction=" + py_literal(d.fraction) + ", boundary=" + py_literal(d.boundary) + ", save=None, load=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus param` with every option. center -1 (default): the whole mesh, a disk, polygons as "
                       "given, flip-free by method 'perfect' (Algorithm 1: iters, eps), 'cotan' or 'uniform'; "
                       "returns .uv (nv, 2). center >= 0: the patch of round(fraction * nv) vertices around it from "
                       "the global factor of -L + eps M (boundary 'neumann' or 'circle'; save / load: a factor "
                       "cache file); returns .vertices, .F (the patch's triangles), .uv (patch size, 2). Both: the "
                       "CLI's statistics (.flipped_faces, .degenerate_faces, ...).\n") +
           kCallArgs).c_str());
}

}  // namespace locus::python
