// locus.Session.perfect_laplacian and .selfsupport: the `perfect-laplacian`
// and `selfsupport` commands with every option of the CLI, as keyword
// arguments of the same names and defaults (engine/include/locus/engine/
// laplacian_requests.hpp). perfect_laplacian still takes its older keywords
// max_iterations (= iters) and newton (False = method 'multiplicative').
// Session.self_supporting stays as it was.
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

py::object perfect_laplacian(const Session& s, bool planar, int32_t iters, double eps, const std::string& method,
                             int32_t anderson, bool no_active_set, double noise, uint64_t seed,
                             const py::handle& max_iterations, const py::handle& newton, int threads,
                             py::object progress) {
  PerfectLaplacianCommandRequest q;
  q.planar = planar;
  q.iters = max_iterations.is_none() ? iters : max_iterations.cast<int32_t>();
  q.eps = eps;
  q.method = newton.is_none() ? method : (newton.cast<bool>() ? "newton" : "multiplicative");
  q.anderson = anderson;
  q.no_active_set = no_active_set;
  q.noise = noise;
  q.seed = seed;
  PerfectLaplacianCommandReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.perfect_laplacian(q, ctx); });
  const auto ne = static_cast<py::ssize_t>(r.weights.size());
  const auto nv = static_cast<py::ssize_t>(r.xyz.size() / 3);
  py::dict d("edges"_a = take(std::move(r.edges), {ne, 2}), "weights"_a = take(std::move(r.weights)),
             "V"_a = take(std::move(r.xyz), {nv, 3}), "converged"_a = r.converged, "iterations"_a = r.iterations,
             "max_displacement_rel"_a = r.max_displacement_rel, "mean_displacement_rel"_a = r.mean_displacement_rel);
  d["mode"] = r.mode;
  d["boundary_on_circle"] = r.boundary_on_circle;
  d["boundary_loops"] = r.boundary_loops;
  d["pinned_vertices"] = r.pinned_vertices;
  d["last_change_rel"] = r.last_change_rel;
  d["min_weight"] = r.min_weight;
  d["min_positive_weight"] = r.min_positive_weight;
  d["zero_weights"] = r.zero_weights;
  d["weights_at_floor"] = r.weights_at_floor;
  d["weights_revived"] = r.weights_revived;
  d["kkt_rounds"] = r.kkt_rounds;
  d["kkt_violation"] = r.kkt_violation;
  d["align_scale"] = r.align_scale;
  d["factorizations"] = r.factorizations;
  d["hessian_products"] = r.hessian_products;
  d["first_iter_s"] = r.first_iter_s;
  d["iter_s"] = r.iter_s;
  return result(d);
}

py::object selfsupport(const Session& s, const std::string& support, double load_density, int32_t iters, double eps,
                       int threads, py::object progress) {
  SelfSupportCommandRequest q;
  q.support = support;
  q.load_density = load_density;
  q.iters = iters;
  q.eps = eps;
  SelfSupportCommandReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.self_supporting(q, ctx); });
  const auto ne = static_cast<py::ssize_t>(r.forces.size());
  const auto nv = static_cast<py::ssize_t>(r.xyz.size() / 3);
  return result(py::dict("edges"_a = take(std::move(r.edges), {ne, 2}), "forces"_a = take(std::move(r.forces)),
                         "V"_a = take(std::move(r.xyz), {nv, 3}), "converged"_a = r.converged,
                         "iterations"_a = r.iterations, "residual_rel"_a = r.residual_rel, "min_force"_a = r.min_force,
                         "max_force"_a = r.max_force, "zero_forces"_a = r.zero_forces,
                         "max_displacement_rel"_a = r.max_displacement_rel,
                         "mean_displacement_rel"_a = r.mean_displacement_rel, "first_iter_s"_a = r.first_iter_s,
                         "iter_s"_a = r.iter_s));
}

}  // namespace

void bind_session_laplacian_commands(SessionClass& cls) {
  const PerfectLaplacianCommandRequest p;
  cls.def("perfect_laplacian", &perfect_laplacian, "planar"_a = p.planar, py::kw_only(), "iters"_a = p.iters,
          "eps"_a = p.eps, "method"_a = p.method, "anderson"_a = p.anderson, "no_active_set"_a = p.no_active_set,
          "noise"_a = p.noise, "seed"_a = p.seed, "max_iterations"_a = py::none(), "newton"_a = py::none(),
          "threads"_a = 0, "progress"_a = py::none(),
          (std::string("perfect_laplacian(planar=" + py_literal(p.planar) + ", *, iters=" + py_literal(p.iters) + ", eps=" + py_literal(p.eps) + ", method=" + py_literal(p.method) + ", anderson=" + py_literal(p.anderson) + ", no_active_set=" + py_literal(p.no_active_set) + ", noise=" + py_literal(p.noise) + ", seed=" + py_literal(p.seed) + ", max_iterations=None, newton=None" + ", threads=0, progress=None) -> namespace\n\n" + "`locus perfect-laplacian` with every option: Algorithm 1 of thesis ch. 2 on the faces as "
                       "given. planar: use x, y only (one boundary loop). iters, eps: the iteration cap and "
                       "tolerance; method: 'newton' or 'multiplicative' (anderson: its acceleration depth); "
                       "no_active_set: keep iterating every weight; noise, seed: seeded noise of up to noise * h "
                       "per coordinate first. Older spellings: max_iterations (= iters), newton (False = "
                       "'multiplicative'). Returns .edges ((ne, 2), v0 < v1), .weights (unit 2-norm), .V (the "
                       "embedding, aligned onto the input in space), .converged, .iterations and the CLI's "
                       "statistics.\n") +
           kCallArgs).c_str());
  const SelfSupportCommandRequest d;
  cls.def("selfsupport", &selfsupport, "support"_a = d.support, py::kw_only(), "load_density"_a = d.load_density,
          "iters"_a = d.iters, "eps"_a = d.eps, "threads"_a = 0, "progress"_a = py::none(),
          (std::string("selfsupport(support=" + py_literal(d.support) + ", *, load_density=" + py_literal(d.load_density) + ", iters=" + py_literal(d.iters) + ", eps=" + py_literal(d.eps) + std::string("") + ", threads=0, progress=None) -> namespace\n\n" + "`locus selfsupport` with every option: a self-supporting surface (thesis §2.6, eq. 2.12), "
                       "supports on the boundary, dead load load_density per unit area. Returns .edges, .forces "
                       "(per edge, >= 0), .V (the equilibrium surface) and the CLI's statistics.\n") +
           kCallArgs).c_str());
}

}  // namespace locus::python
