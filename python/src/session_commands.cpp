// locus.Session.geodesic and locus.Session.logmap: the `geodesic` and
// `logmap` commands with every option of the CLI, as keyword arguments of the
// same names and defaults (engine/include/locus/engine/geodesic_requests.hpp),
// returning the values and the statistics the CLI reports.
#include <cmath>
#include <cstdio>
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

// t: None (the default), a str in the CLI's grammar ("4h2", "0.001") or a
// number (an absolute time).
std::string time_text(const py::handle& t) {
  if (t.is_none()) return {};
  if (py::isinstance<py::str>(t)) return t.cast<std::string>();
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", t.cast<double>());
  return buf;
}

std::optional<double> optional_number(const py::handle& x) {
  if (x.is_none()) return std::nullopt;
  return x.cast<double>();
}

py::object cache_dict(const FactorCacheReport& c) {
  if (!c.used()) return py::none();
  return py::dict("loaded"_a = c.loaded.empty() ? py::object(py::none()) : py::object(py::str(c.loaded)),
                  "saved"_a = c.saved.empty() ? py::object(py::none()) : py::object(py::str(c.saved)),
                  "load_s"_a = c.load_s, "save_s"_a = c.save_s);
}

py::object geodesic(const Session& s, int64_t source, double fraction, const py::handle& t, const py::handle& t_factor,
                    const py::handle& save, const py::handle& load, int threads, py::object progress) {
  GeodesicRequest q;
  q.source = source;
  q.fraction = fraction;
  q.t = time_text(t);
  q.t_factor = optional_number(t_factor);
  q.save = optional_text(save);
  q.load = optional_text(load);
  GeodesicReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.geodesic(q, ctx); });
  std::vector<int32_t> valid(r.valid.begin(), r.valid.end());
  return result(py::dict(
      "distance"_a = take(std::move(r.distance)), "valid"_a = take(std::move(valid)), "source"_a = r.source,
      "method"_a = r.method, "fraction"_a = r.fraction, "t_factor"_a = r.t_factor, "t_spec"_a = r.t_spec, "t"_a = r.t,
      "h"_a = r.h, "patch_size"_a = r.patch_size, "max_distance"_a = r.max_distance, "unreachable"_a = r.unreachable,
      "heat_underflow_vertices"_a = r.heat_underflow_vertices, "t_avoiding_underflow"_a = r.t_avoiding_underflow,
      "warnings"_a = r.warnings, "precompute_s"_a = r.precompute_s, "patch_s"_a = r.patch_s, "query_s"_a = r.query_s,
      "factor_cache"_a = cache_dict(r.factor_cache)));
}

py::object logmap(const Session& s, int64_t center, double fraction, const py::handle& t, const py::handle& t_factor,
                  const std::string& method, const std::string& angle, const std::string& lattice,
                  const std::string& recenter, bool clip_injective, const py::handle& save, const py::handle& load,
                  int threads, py::object progress) {
  LogmapRequest q;
  q.center = center;
  q.fraction = fraction;
  q.t = time_text(t);
  q.t_factor = optional_number(t_factor);
  q.method = method;
  q.angle = angle;
  q.lattice = lattice;
  q.recenter = recenter;
  q.clip_injective = clip_injective;
  q.save = optional_text(save);
  q.load = optional_text(load);
  LogmapReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.logmap(q, ctx); });
  py::dict d("patch"_a = take(std::move(r.patch)), "distance"_a = take(std::move(r.distance)),
             "angle"_a = take(std::move(r.angle)), "u"_a = take(std::move(r.u)), "v"_a = take(std::move(r.v)));
  d["center"] = r.center;
  d["method"] = r.method;
  d["angle_estimator"] = r.angle_estimator;
  d["fraction"] = r.fraction;
  d["t_factor"] = r.t_factor;
  d["t_spec"] = r.t_spec;
  d["t"] = r.t;
  d["h"] = r.h;
  d["sources"] = r.sources;
  d["batches"] = r.batches;
  d["passes"] = r.passes;
  d["two_ring"] = r.two_ring;
  d["recentered"] = r.recentered;
  d["angle_fallbacks"] = r.angle_fallbacks;
  d["heat_underflow_vertices"] = r.heat_underflow_vertices;
  d["t_avoiding_underflow"] = r.t_avoiding_underflow;
  d["warnings"] = r.warnings;
  d["max_distance"] = r.max_distance;
  d["flipped"] = r.flipped;
  d["injectivity_radius"] = std::isfinite(r.injectivity_radius) ? py::object(py::float_(r.injectivity_radius))
                                                                  : py::object(py::none());
  d["clipped_vertices"] = r.clipped_vertices;
  d["precompute_s"] = r.precompute_s;
  d["patch_s"] = r.patch_s;
  d["query_s"] = r.query_s;
  d["factor_cache"] = cache_dict(r.factor_cache);
  return result(d);
}

}  // namespace

void bind_session_commands(SessionClass& cls) {
  const LogmapRequest d;
  cls.def("geodesic", &geodesic, "source"_a, py::kw_only(), "fraction"_a = GeodesicRequest{}.fraction,
          "t"_a = py::none(), "t_factor"_a = py::none(), "save"_a = py::none(), "load"_a = py::none(),
          "threads"_a = 0, "progress"_a = py::none(),
          (std::string("geodesic(source, *, fraction=1.0, t=None, t_factor=None, save=None, load=None, threads=0, "
                       "progress=None) -> namespace\n\n"
                       "`locus geodesic` with every option: heat geodesic distance from vertex `source` on the whole "
                       "mesh (fraction 1) or localized to the geodesic disk of round(fraction * nv) vertices (exact "
                       "subset solves). Returns .distance (nv,) float64, NaN without a value, .valid (nv,) int32 and "
                       "the CLI's statistics (.method, .t, .h, .patch_size, .max_distance, .unreachable, "
                       ".heat_underflow_vertices, .warnings, ...).\n"
                       "t: diffusion time, a str ('4h2': a multiple of h^2, h the mean edge length; '0.001') or a "
                       "number (absolute); None: 4h2 (8h2 on polygon meshes). t_factor: t = t_factor * h^2 (not "
                       "with t). save / load: a factor cache file written after factoring / read instead.\n") +
           kCallArgs).c_str());
  cls.def("logmap", &logmap, "center"_a, "fraction"_a = d.fraction, py::kw_only(), "t"_a = py::none(),
          "t_factor"_a = py::none(), "method"_a = d.method, "angle"_a = d.angle, "lattice"_a = d.lattice,
          "recenter"_a = d.recenter, "clip_injective"_a = d.clip_injective, "save"_a = py::none(),
          "load"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
          (std::string("logmap(center, fraction=0.05, *, t=None, t_factor=None, method='heat', angle='auto', "
                       "lattice='default', recenter='default', clip_injective=False, save=None, load=None, "
                       "threads=0, progress=None) -> namespace\n\n"
                       "`locus logmap` with every option: the log map (thesis §6.5–6.6) of the geodesic disk of "
                       "round(fraction * nv) vertices around `center`. Polygon meshes: the polygon log map with full "
                       "solves on the disk grown over the polygon edges.\n"
                       "Returns .patch (int32 vertex ids, center first) and per patch vertex .distance, .angle "
                       "(radians), .u, .v = distance * (cos, sin)(angle); and the CLI's statistics (.flipped, "
                       ".injectivity_radius (None: none flipped), .clipped_vertices, .sources, .batches, "
                       ".heat_underflow_vertices, .warnings, ...).\n"
                       "method: 'heat' (localized), 'heat-full' or 'dem'. angle: 'auto', 'log', 'two-ring' or "
                       "'average'. lattice: 'default', 'none', 'star', 'ring' or 'path'. recenter: 'default', 'on' "
                       "or 'off'. clip_injective: keep only the vertices inside the injectivity radius. t, t_factor, "
                       "save, load: as geodesic().\n") +
           kCallArgs).c_str());
}

void bind_request_fields(py::module_& m) {
  m.def(
      "request_fields",
      [](const std::string& command) {
        py::list out;
        for (const RequestField& f : locus::request_fields(command)) out.append(py::make_tuple(f.name, f.default_value));
        return out;
      },
      "command"_a,
      "request_fields(command) -> [(name, default)]\n\nThe fields of the engine's request of a command ('geodesic', "
      "'logmap', 'adf', 'hks', 'heat', 'deform', 'nncoords', 'param', 'perfect-laplacian', 'selfsupport') with "
      "their defaults as text ('' = none): the CLI's options, '-' as '_'.");
}

}  // namespace locus::python
