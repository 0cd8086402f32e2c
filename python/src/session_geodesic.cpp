// locus.Session: the heat method (thesis §6.4–6.6) — geodesic distance from
// vertices and points (the log map and the geodesic command: session_commands.cpp)
// — and heat values by exact subset solves (ch. 4), random surface points.
#include <string>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

HeatQuery heat(double t_factor, double t = 0.0) {
  HeatQuery q;
  q.t_factor = t_factor;
  q.t = t;
  return q;
}

py::object geodesic_distance(const Session& s, const py::handle& sources, const py::handle& t_factor_arg,
                             const py::handle& out, int threads, py::object progress) {
  const double t_factor = heat_method_t_factor(t_factor_arg);
  const size_t nv = static_cast<size_t>(s.num_vertices());
  py::object array = py::reinterpret_borrow<py::object>(out);
  if (out.is_none()) array = py::array_t<double>(static_cast<py::ssize_t>(nv));
  const View<double> dst = out_view(array, nv, "out");
  const HeatQuery q = heat(t_factor);
  if (py::isinstance<py::int_>(sources) || (py::hasattr(sources, "__index__") && !py::hasattr(sources, "__len__"))) {
    // One vertex: the heat method from a single source, as `locus geodesic --source`.
    const int32_t v = vertex_id(sources, static_cast<int64_t>(nv), "geodesic_distance: source");
    run({threads, progress}, [&](const RunContext& ctx) { s.geodesic_distance(v, dst, q, ctx); });
  } else {
    const std::vector<MeshPoint> pts = mesh_points(sources, "sources");
    run({threads, progress}, [&](const RunContext& ctx) { s.geodesic_distance(ConstView<MeshPoint>(pts), dst, q, ctx); });
  }
  return array;
}

py::array heat_values(const Session& s, const py::handle& sources, const py::handle& targets, double t_factor, double t,
                      int threads, py::object progress) {
  const std::vector<int32_t> src = vertex_ids(sources, "sources"), dst = vertex_ids(targets, "targets");
  std::vector<double> values;
  run({threads, progress}, [&](const RunContext& ctx) {
    values = s.heat_values(ConstView<int32_t>(src), ConstView<int32_t>(dst), heat(t_factor, t), ctx);
  });
  return take(std::move(values), {py::ssize_t(src.size()), py::ssize_t(dst.size())});
}

}  // namespace

void bind_session_geodesic(SessionClass& cls) {
  cls.def("geodesic_distance", &geodesic_distance, "sources"_a, py::kw_only(), "t_factor"_a = py::none(), "out"_a = py::none(),
          "threads"_a = 0, "progress"_a = py::none(),
          (std::string("geodesic_distance(sources, *, t_factor=None, out=None, threads=0, progress=None) -> ndarray\n\n"
                       "Heat geodesic distance (thesis §6.4; Crane et al.) to every vertex, in the units of the "
                       "positions: float64 array of shape (nv,).\n"
                       "sources: a vertex id (int), a 1-D array of vertex ids, or (faces, bary) points in faces "
                       "(bary: (k, 3) barycentric weights of the face's corners). With several sources the "
                       "distance is shifted so that its minimum over each component's sources is 0. NaN (no value) "
                       "in components without a source (with one source too).\n"
                       "t_factor: diffusion time t = t_factor * h^2, h the mean edge length (None: the CLI's default, 4 "
                       "on triangle meshes, where the angles of log maps are ~4x more accurate than at 1 for the "
                       "same cost; 8 on polygon meshes, where the distance runs on the polygons themselves, with "
                       "h their mean edge). The first query per t_factor factors two operators; later ones reuse "
                       "them (stats()).\n"
                       "out: a float64 C-contiguous array of shape (nv,) to write into (no allocation); returned.\n") +
           kCallArgs).c_str());
  cls.def("heat_values", &heat_values, "sources"_a, "targets"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0,
          "threads"_a = 0, "progress"_a = py::none(),
          (std::string("heat_values(sources, targets, *, t_factor=1.0, t=0.0, threads=0, progress=None) -> ndarray\n\n"
                       "Entries (M - tL)^{-1}[target, source] by exact subset solves (thesis ch. 4): float64 array "
                       "of shape (len(sources), len(targets)).\n"
                       "t: absolute diffusion time (units of length^2); 0 (default) = t_factor * h^2.\n") +
           kCallArgs).c_str());
  cls.def(
      "random_points",
      [](const Session& s, int32_t count, uint64_t seed) { return face_points(s.random_points(count, seed)); },
      "count"_a, "seed"_a = 1,
      "random_points(count, seed=1) -> (faces, bary)\n\n"
      "`count` points uniformly distributed by area (splitmix64 from `seed`, the same on every platform; "
      "`locus voronoi --random N --seed S` uses these): faces (int32, (count,)) and barycentric weights "
      "(float64, (count, 3)). Pass the tuple wherever surface points are accepted.");
}

}  // namespace locus::python
