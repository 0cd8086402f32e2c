// locus.Session.factor_command: the `factor` command with every option of the
// CLI, as keyword arguments of the same names and defaults
// (engine/include/locus/engine/factor_request.hpp): the numeric core end to
// end on the Session's mesh, its timings and residuals.
#include <string>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "locus/engine/factor_request.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

py::object run_factor_command(const Session& s, const std::string& matrix, const py::handle& t, int32_t repeat,
                              const py::handle& save, const py::handle& load, uint64_t seed, int threads,
                              py::object progress) {
  FactorCommandRequest q;
  q.matrix = matrix;
  q.t = optional_text(t);
  q.repeat = repeat;
  q.save = optional_text(save);
  q.load = optional_text(load);
  q.seed = seed;
  FactorCommandReport r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.factor(q, ctx); });
  return result(py::dict(
      "x"_a = take(std::move(r.x)), "matrix"_a = r.matrix, "t"_a = r.t, "h"_a = r.h, "repeats"_a = r.repeats,
      "n"_a = r.n, "nnz_A"_a = r.nnz_A, "nnz_L"_a = r.nnz_L, "nnz_L_exact"_a = r.nnz_L_exact,
      "supernodes"_a = r.supernodes, "etree_height"_a = r.etree_height, "super_etree_height"_a = r.super_etree_height,
      "flops"_a = r.flops, "residual"_a = r.residual, "residual8"_a = r.residual8,
      "solve8_lane0_vs_solve"_a = r.lane0_vs_solve, "operator_s"_a = r.operator_s, "order_s"_a = r.order_s,
      "symbolic_s"_a = r.symbolic_s, "numeric_s"_a = r.numeric_s, "solve_s"_a = r.solve_s, "solve8_s"_a = r.solve8_s,
      "load_s"_a = r.factor_cache.load_s, "save_s"_a = r.factor_cache.save_s));
}

}  // namespace

void bind_session_factor_command(SessionClass& cls) {
  const FactorCommandRequest d;
  cls.def("factor_command", &run_factor_command, py::kw_only(), "matrix"_a = d.matrix, "t"_a = py::none(),
          "repeat"_a = d.repeat, "save"_a = py::none(), "load"_a = py::none(), "seed"_a = d.seed, "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("factor_command(*, matrix=") + py_literal(d.matrix) + ", t=None, repeat=" +
           py_literal(d.repeat) + ", save=None, load=None, seed=" + py_literal(d.seed) +
           ", threads=0, progress=None) -> namespace\n\n"
           "`locus factor` with every option: the cotan heat matrix M - tL (matrix='heat', t as the CLI's: "
           "'h2' by default, a multiple of h^2, or absolute) or the regularized Laplacian (matrix='laplacian') "
           "ordered, analyzed, factored (or loaded from `load`, written to `save`) and solved for a seeded random "
           "right-hand side, `repeat` times. Returns .x (the last 1-lane solution), the factor's sizes, the "
           "medians of the phases' seconds and the residuals (locus.NumericalError when the solve is "
           "inaccurate).\n" +
           kCallArgs)
              .c_str());
}

}  // namespace locus::python
