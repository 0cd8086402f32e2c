// locus.Session.skinweights_command: the `skinweights` command with every
// option of the CLI, as keyword arguments of the same names and defaults
// (engine/include/locus/engine/skinning_requests.hpp; thesis §3.7.2): handles
// as vertices or vertex sets, bones as polylines, the sampled method (default)
// or the exact one. Session.skinning_weights (handles as surface points, one
// natural-neighbor solve per vertex) stays the cached tier.
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "locus/engine/skinning_requests.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

// handles: an int (one vertex), or a sequence whose items are vertex ids or
// sequences of vertex ids (one handle each).
std::vector<std::vector<int64_t>> handle_sets(const py::handle& handles) {
  std::vector<std::vector<int64_t>> out;
  if (handles.is_none()) return out;
  if (py::isinstance<py::int_>(handles)) return {{handles.cast<int64_t>()}};
  for (const py::handle h : handles) {
    if (py::isinstance<py::int_>(h) || (py::hasattr(h, "__index__") && !py::hasattr(h, "__len__"))) {
      out.push_back({py::reinterpret_borrow<py::object>(h).attr("__index__")().cast<int64_t>()});
      continue;
    }
    const std::vector<int32_t> ids = vertex_ids(h, "handles");
    out.emplace_back(ids.begin(), ids.end());
  }
  return out;
}

// bone: a sequence of polylines, each (k, 3) points or 3k numbers.
std::vector<std::vector<double>> bone_polylines(const py::handle& bone) {
  std::vector<std::vector<double>> out;
  if (bone.is_none()) return out;
  const py::module_ np = py::module_::import("numpy");
  for (const py::handle b : bone) {
    const py::array a = np.attr("asarray")(b, "dtype"_a = "float64").attr("ravel")();
    out.push_back(a.cast<std::vector<double>>());
  }
  return out;
}

py::object run_skinweights_command(const Session& s, const py::handle& handles, const py::handle& bone, bool exact,
                                   int32_t samples, const std::string& t, int threads, py::object progress) {
  SkinningRequest q;
  q.handles = handle_sets(handles);
  q.bone = bone_polylines(bone);
  q.exact = exact;
  q.samples = samples;
  q.t = t;
  SkinningReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.skinning(q, ctx); });
  py::list sets;
  for (std::vector<int32_t>& h : r.handle_vertices) sets.append(take(std::move(h)));
  const py::ssize_t nv = s.num_vertices(), k = r.handles;
  return result(py::dict("weights"_a = take(std::move(r.weight), {nv, k}), "handle_vertices"_a = sets,
                         "method"_a = r.method, "samples"_a = r.samples, "sample_rings"_a = r.sample_rings,
                         "radius"_a = r.radius, "coarse_vertices"_a = r.coarse_vertices, "degenerate_vertices"_a = r.degenerate_vertices,
                         "fallback_faces"_a = r.fallback_faces, "max_clamped"_a = r.max_clamped, "t"_a = r.t,
                         "factor_s"_a = r.factor_s, "prepare_s"_a = r.prepare_s, "weights_s"_a = r.weights_s,
                         "propagate_s"_a = r.propagate_s));
}

}  // namespace

void bind_session_skinweights_command(SessionClass& cls) {
  const SkinningRequest d;
  cls.def("skinweights_command", &run_skinweights_command, "handles"_a = py::none(), py::kw_only(),
          "bone"_a = py::none(), "exact"_a = d.exact, "samples"_a = d.samples, "t"_a = d.t, "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("skinweights_command(handles=None, *, bone=None, exact=" + py_literal(d.exact) +
                       ", samples=" + py_literal(d.samples) + ", t=" + py_literal(d.t) +
                       ", threads=0, progress=None) -> namespace\n\n") +
           "`locus skinweights` with every option: natural-neighbor skinning weights (thesis §3.7.2). handles: "
           "vertex ids, or lists of vertex ids (a vertex set is one handle); bone: polylines ((k, 3) points, "
           "k >= 2; a bone is the vertices nearest to it), after the handles. exact: natural-neighbor coordinates "
           "at every vertex (slow); else the sampled method with at most `samples` exact rows (0: 1024), on a "
           "coarse level of the mesh when it has more than 48,000 vertices (.method 'coarse'). t: '' "
           "(h^2), a multiple of h^2 ('4h2') or absolute. Returns .weights (float64 (nv, handles), rows sum to 1), "
           ".handle_vertices, .method, .samples, .sample_rings, .radius, .coarse_vertices and the CLI's statistics.\n" +
           kCallArgs)
              .c_str());
}

}  // namespace locus::python
