// locus.Session.adf, .hks and .heat: the `adf`, `hks` and `heat` commands
// with every option of the CLI, as keyword arguments of the same names and
// defaults (engine/include/locus/engine/diffusion_requests.hpp), returning the
// values and the statistics the CLI reports. Session.auto_diffusion,
// .heat_kernel_signature and .heat_exchange stay the cached tier.
#include <cmath>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

std::vector<int64_t> ids_of(const py::handle& ids, const char* name) {
  if (ids.is_none()) return {};
  const std::vector<int32_t> v = vertex_ids(ids, name);
  return std::vector<int64_t>(v.begin(), v.end());
}

py::object cache_dict(const FactorCacheReport& c) {
  if (!c.used()) return py::none();
  return py::dict("loaded"_a = c.loaded.empty() ? py::object(py::none()) : py::object(py::str(c.loaded)),
                  "saved"_a = c.saved.empty() ? py::object(py::none()) : py::object(py::str(c.saved)),
                  "load_s"_a = c.load_s, "save_s"_a = c.save_s);
}

// values: (evaluated,) for adf, (evaluated, len(ts)) for hks.
py::object signature_result(HeatSignatureReport&& r, bool adf) {
  const auto rows = static_cast<py::ssize_t>(r.count());
  const auto nt = static_cast<py::ssize_t>(r.t.size());
  py::array values = adf ? take(std::move(r.values)) : take(std::move(r.values), {rows, nt});
  py::object t = adf ? py::object(py::float_(r.t[0])) : py::object(py::cast(r.t));
  py::object t_spec = adf ? py::object(py::str(r.t_spec[0])) : py::object(py::cast(r.t_spec));
  return result(py::dict("values"_a = values, "vertices"_a = take(std::move(r.vertices)), "all"_a = r.all,
                         "method"_a = r.method, "n"_a = r.n, "h"_a = r.h, "t"_a = t, "t_spec"_a = t_spec,
                         "nnz_L"_a = r.nnz_L, "supernodes"_a = r.supernodes, "etree_height"_a = r.etree_height,
                         "operator_s"_a = r.operator_s, "order_s"_a = r.order_s, "analyze_s"_a = r.analyze_s,
                         "numeric_s"_a = r.numeric_s, "factor_s"_a = r.factor_s(), "query_s"_a = r.query_s,
                         "factor_cache"_a = cache_dict(r.factor_cache)));
}

// The arguments adf and hks share: the vertices (or all), the method, the factor cache files.
template <class Request>
void set_signature_options(Request& q, const py::handle& vertices, bool all, const std::string& method,
                           const py::handle& save, const py::handle& load) {
  q.vertices = ids_of(vertices, "vertices");
  q.all = all;
  q.method = method;
  q.save = optional_text(save);
  q.load = optional_text(load);
}

py::object adf(const Session& s, const std::string& t, const py::handle& vertices, bool all, const std::string& method,
               const py::handle& save, const py::handle& load, int threads, py::object progress) {
  AdfRequest q;
  q.t = t;
  set_signature_options(q, vertices, all, method, save, load);
  HeatSignatureReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.adf(q, ctx); });
  return signature_result(std::move(r), true);
}

py::object hks(const Session& s, const std::vector<std::string>& ts, const py::handle& vertices, bool all,
               const std::string& method, const py::handle& save, const py::handle& load, int threads,
               py::object progress) {
  HksRequest q;
  q.ts = ts;
  set_signature_options(q, vertices, all, method, save, load);
  HeatSignatureReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.hks(q, ctx); });
  return signature_result(std::move(r), false);
}

py::object heat(const Session& s, const py::handle& source, const py::handle& target, const std::string& t,
                const std::string& method, int repeat, const py::handle& save, const py::handle& load, int threads,
                py::object progress) {
  HeatRequest q;
  q.source = ids_of(source, "source");
  q.target = ids_of(target, "target");
  q.t = t;
  q.method = method;
  q.repeat = repeat;
  q.save = optional_text(save);
  q.load = optional_text(load);
  HeatReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.heat(q, ctx); });
  return result(py::dict(
      "values"_a = take(std::move(r.values)), "total"_a = r.total, "sources"_a = take(std::move(r.sources)),
      "targets"_a = take(std::move(r.targets)), "method"_a = r.method, "n"_a = r.n, "t"_a = r.t, "h"_a = r.h,
      "t_spec"_a = r.t_spec, "nnz_L"_a = r.nnz_L, "etree_height"_a = r.etree_height,
      "forward_columns"_a = r.forward_columns, "backward_columns"_a = r.backward_columns, "repeats"_a = r.repeats,
      "operator_s"_a = r.operator_s, "order_s"_a = r.order_s, "analyze_s"_a = r.analyze_s,
      "numeric_s"_a = r.numeric_s, "factor_s"_a = r.factor_s(), "query_s"_a = r.query_s, "plan_s"_a = r.plan_s,
      "solve_s"_a = r.solve_s, "factor_cache"_a = cache_dict(r.factor_cache)));
}

py::object nncoords(const Session& s, const py::handle& sites, const py::handle& point, const std::string& t,
                    int threads, py::object progress) {
  NncoordsRequest q;
  q.sites = ids_of(sites, "sites");
  const py::array p = py::module_::import("numpy").attr("asarray")(point, "dtype"_a = "float64").attr("ravel")();
  if (p.size() != 4) usage_error("point must be (face, b0, b1, b2), got " + std::to_string(p.size()) + " numbers");
  const auto* v = static_cast<const double*>(p.data());
  if (!(v[0] >= 0 && v[0] < 2147483647.0) || v[0] != std::floor(v[0]))
    usage_error("point: the face must be a non-negative integer id");
  q.point.face = static_cast<int64_t>(v[0]);
  q.point.bary = {v[1], v[2], v[3]};
  q.t = t;
  NncoordsReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.nncoords(q, ctx); });
  return result(py::dict("weights"_a = take(std::move(r.weights)),
                         "natural_neighbors"_a = take(std::move(r.natural_neighbors)), "cell_area"_a = r.cell_area,
                         "at_site"_a = r.at_site, "degenerate"_a = r.degenerate, "clamped"_a = r.clamped,
                         "fallback_faces"_a = r.fallback_faces, "t"_a = r.t, "prepare_s"_a = r.prepare_s,
                         "query_s"_a = r.query_s));
}

}  // namespace

void bind_session_diffusion_commands(SessionClass& cls) {
  const AdfRequest a;
  const HksRequest k;
  const HeatRequest h;
  cls.def("adf", &adf, "t"_a = a.t, py::kw_only(), "vertices"_a = py::none(), "all"_a = a.all, "method"_a = a.method,
          "save"_a = py::none(), "load"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
          (std::string("adf(t=" + py_literal(a.t) + ", *, vertices=None, all=" + py_literal(a.all) + ", method=" + py_literal(a.method) + ", save=None, load=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus adf` with every option: (M - tL)^{-1}_ii (thesis §4.6) at `vertices` or, with "
                       "all=True, at every vertex (exactly one of the two). t: '1h2' (a multiple of h^2, h the mean "
                       "edge length) or an absolute time ('0.001'). method: 'subset', 'selinv' or 'full'. save / "
                       "load: a factor cache file. Returns .values (one per evaluated vertex), .vertices and the "
                       "CLI's statistics (.t, .h, .nnz_L, .etree_height, .factor_s, ...).\n") +
           kCallArgs).c_str());
  cls.def("hks", &hks, "ts"_a, py::kw_only(), "vertices"_a = py::none(), "all"_a = k.all, "method"_a = k.method,
          "save"_a = py::none(), "load"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
          (std::string("hks(ts, *, vertices=None, all=" + py_literal(k.all) + ", method=" + py_literal(k.method) + ", save=None, load=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus hks` with every option: adf() at several times `ts` (a list of str, as t of adf). "
                       "Returns .values (evaluated, len(ts)) and the statistics of adf().\n") +
           kCallArgs).c_str());
  cls.def("heat", &heat, "source"_a, "target"_a, py::kw_only(), "t"_a = h.t, "method"_a = h.method,
          "repeat"_a = h.repeat, "save"_a = py::none(), "load"_a = py::none(), "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("heat(source, target, *, t=" + py_literal(h.t) + ", method=" + py_literal(h.method) + ", repeat=" + py_literal(h.repeat) + ", save=None, load=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus heat` with every option: unit heat at every `source` vertex (repeats add), one "
                       "backward-Euler step of M - tL, the heat at each `target`. method: 'subset', 'union' or "
                       "'full'; repeat: run the query that many times (median timings). Returns .values (per "
                       "target), .total and the CLI's statistics.\n") +
           kCallArgs).c_str());
  cls.def("nncoords", &nncoords, "sites"_a, "point"_a, py::kw_only(), "t"_a = NncoordsRequest{}.t, "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("nncoords(sites, point, *, t=" + py_literal(NncoordsRequest{}.t) + std::string("") + ", threads=0, progress=None) -> namespace\n\n" + "`locus nncoords` with every option: natural-neighbor (area-stealing) coordinates of `point` "
                       "= (face, b0, b1, b2), a point in a triangle by its barycentric weights, with respect to the "
                       "vertex `sites` (thesis §3.7.2), with heat Voronoi cells at time t ('h2', a multiple of h^2, "
                       "or absolute). Returns .weights (one per site), .natural_neighbors and the CLI's statistics. "
                       "prepare_natural_neighbors serves many points.\n") +
           kCallArgs).c_str());
}

}  // namespace locus::python
