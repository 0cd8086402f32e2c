// The matrix `locus factor` and the benchmarks factor: --matrix heat|laplacian
// (its older spelling --operator heat|laplacian, an alias) and --t T, built by
// the engine (locus/engine/factor_request.hpp: factor_matrix).
#pragma once
#include <string>

#include "locus/engine/factor_request.hpp"
#include "locus/mesh.hpp"
#include "tools/cli/cli_command_table.hpp"

namespace locus::cli {

struct OperatorSpec {
  std::string kind = "heat";  // "heat": M - t L_C;  "laplacian": -L_C + eps M
  std::string t_text;         // --t as given ("" = default h^2)
};
using BuiltOperator = FactorMatrix;  // A, the t used (0 for the Laplacian), the mean edge length h

// Adds --matrix, its alias --operator (in place of the common --operator
// auto|cotan|robust: these matrices are the cotan ones) and --t, bound to
// `matrix` and `t`.
void add_matrix_options(CLI::App* app, std::string& matrix, std::string& t);
inline void add_operator_options(CLI::App* app, OperatorSpec& spec) { add_matrix_options(app, spec.kind, spec.t_text); }
// Checks the spec before any work (BadUsage: --t with the Laplacian, bad --t).
void validate_operator_spec(const OperatorSpec& spec);
// Checks the mesh suits the operators (triangles, manifold, no degenerate
// faces, no unreferenced vertices; BadInput otherwise) and builds A.
BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec);

}  // namespace locus::cli
