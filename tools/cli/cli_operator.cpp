// --operator and --t of the commands that factor one operator (cli_operator.hpp).
#include "tools/cli/cli_operator.hpp"

#include <cmath>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "tools/cli/cli_heat_time.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

void add_operator_options(CLI::App* app, OperatorSpec& spec) {
  drop_mesh_operator_option(app);  // this --operator names the matrix
  app->add_option("--operator", spec.kind, "Operator: heat (M - tL, default) or laplacian (-L + eps M)")
      ->check(CLI::IsMember({"heat", "laplacian"}));
  app->add_option("--t", spec.t_text, "Diffusion time of the heat operator: absolute (1e-3) or a multiple of h^2 (2h2); default h2")->check(non_empty());
}

void validate_operator_spec(const OperatorSpec& spec) {
  if (spec.kind == "laplacian" && !spec.t_text.empty())
    fail(ErrorCode::BadUsage, "--t applies to --operator heat only");
  if (!spec.t_text.empty()) parse_time_spec(spec.t_text);
}

BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec) {
  validate_operator_spec(spec);
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  // One edge incidence for the checks, h and the assembly (each would build its own).
  const EdgeIncidence inc = edge_incidence(m);
  check_requirements(m, MeshRequirements{}, analyze_mesh(m, inc));
  BuiltOperator op;
  op.h = mean_edge_length(m, inc.edges);
  if (!(op.h > 0) || !std::isfinite(op.h))
    fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(op.h) + ", cannot scale the operator");
  if (spec.kind == "laplacian") {
    op.A = regularized_laplacian(m, kLaplacianRegularization, &inc);
  } else {
    op.t = spec.t_text.empty() ? op.h * op.h : parse_time_spec(spec.t_text).resolve(op.h);
    op.A = heat_operator(m, op.t, &inc);
  }
  return op;
}

}  // namespace locus::cli
