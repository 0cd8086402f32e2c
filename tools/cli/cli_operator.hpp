// The operators `locus factor` and the benchmarks factor: --operator
// heat|laplacian and --t T.
#pragma once
#include <string>

#include "locus/mesh.hpp"
#include "locus/sparse_matrix.hpp"
#include "tools/cli/cli_command_table.hpp"

namespace locus::cli {

struct OperatorSpec {
  std::string kind = "heat";  // "heat": M - t L_C;  "laplacian": -L_C + eps M
  std::string t_text;         // --t as given ("" = default h^2)
};
struct BuiltOperator {
  CscMatrix A;
  double t = 0;  // diffusion time used (0 for the Laplacian)
  double h = 0;  // mean edge length of the mesh
};
// Adds --operator and --t to a command.
void add_operator_options(CLI::App* app, OperatorSpec& spec);
// Checks the spec before any work (BadUsage: --t with the Laplacian, bad --t).
void validate_operator_spec(const OperatorSpec& spec);
// Checks the mesh suits the operators (triangles, manifold, no degenerate
// faces, no unreferenced vertices; BadInput otherwise) and builds A.
BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec);

}  // namespace locus::cli
