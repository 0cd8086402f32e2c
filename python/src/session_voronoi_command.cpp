// locus.Session.voronoi_command: the `voronoi` command with every option of
// the CLI, as keyword arguments of the same names and defaults
// (engine/include/locus/engine/voronoi_request.hpp). Session.voronoi (the
// generators as points, t as t_factor / absolute) stays the cached tier.
#include <string>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "locus/engine/voronoi_request.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

py::object run_voronoi_command(const Session& s, const py::handle& sites, int32_t random, const std::string& t,
                           const py::handle& save, const py::handle& load, uint64_t seed, int threads,
                           py::object progress) {
  VoronoiCommandRequest q;
  if (!sites.is_none()) {
    const std::vector<int32_t> ids = vertex_ids(sites, "sites");
    q.sites.assign(ids.begin(), ids.end());
  }
  q.random = random;
  q.t = t;
  q.save = optional_text(save);
  q.load = optional_text(load);
  q.seed = seed;
  VoronoiCommandReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.voronoi(q, ctx); });
  const auto ns = static_cast<py::ssize_t>(r.site_xyz.size() / 3);
  const auto np = static_cast<py::ssize_t>(r.points.size() / 3);
  return result(py::dict("labels"_a = take(std::move(r.label)), "sites"_a = take(std::move(r.site_xyz), {ns, 3}),
                         "points"_a = take(std::move(r.points), {np, 3}), "polylines"_a = py::cast(r.polylines),
                         "segments"_a = r.segments, "corners"_a = r.corners, "batches"_a = r.batches,
                         "empty_cells"_a = r.empty_cells, "vertices_without_heat"_a = r.vertices_without_heat,
                         "values_solved_again"_a = r.values_solved_again, "h"_a = r.h, "t"_a = r.t,
                         "prepare_s"_a = r.prepare_s, "solve_s"_a = r.solve_s, "diagram_s"_a = r.diagram_s));
}

}  // namespace

void bind_session_voronoi_command(SessionClass& cls) {
  const VoronoiCommandRequest d;
  cls.def("voronoi_command", &run_voronoi_command, py::kw_only(), "sites"_a = py::none(), "random"_a = d.random,
          "t"_a = d.t, "save"_a = py::none(), "load"_a = py::none(), "seed"_a = d.seed, "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("voronoi_command(*, sites=None, random=" + py_literal(d.random) + ", t=" + py_literal(d.t) + ", save=None, load=None, seed=" + py_literal(d.seed) + std::string("") + ", threads=0, progress=None) -> namespace\n\n" + "`locus voronoi` with every option: the heat Voronoi diagram (thesis §3.4) of the vertex "
                       "`sites` or of `random` seeded random surface points (exactly one), t as the CLI's ('h2': "
                       "a multiple of h^2; or absolute). Returns .labels (per vertex), .sites (generator "
                       "positions), .points and .polylines (the diagram's curves) and the CLI's statistics.\n") +
           kCallArgs).c_str());
}

}  // namespace locus::python
