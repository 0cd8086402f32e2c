// --matrix (alias --operator) and --t of the commands that factor one matrix (cli_operator.hpp).
#include "tools/cli/cli_operator.hpp"

#include "tools/cli/cli_report.hpp"

namespace locus::cli {
namespace {

FactorCommandRequest request_of(const OperatorSpec& spec) {
  FactorCommandRequest q;
  q.matrix = spec.kind;
  q.t = spec.t_text;
  return q;
}

}  // namespace

void add_matrix_options(CLI::App* app, std::string& matrix, std::string& t) {
  drop_mesh_operator_option(app);  // --operator names the matrix here
  CLI::Option* m = app->add_option("--matrix", matrix, "Matrix: heat (M - tL, default) or laplacian (-L + eps M)")
                       ->check(CLI::IsMember({"heat", "laplacian"}));
  app->add_option("--operator", matrix, "Older spelling of --matrix (heat|laplacian); the matrices are the cotan ones")
      ->check(CLI::IsMember({"heat", "laplacian"}))
      ->excludes(m);
  app->add_option("--t", t, "Diffusion time of the heat matrix: absolute (1e-3) or a multiple of h^2 (2h2); default h2")
      ->check(non_empty());
}

void validate_operator_spec(const OperatorSpec& spec) { check_request(request_of(spec)); }

BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec) { return factor_matrix(m, request_of(spec)); }

}  // namespace locus::cli
