// Factors saved to and loaded from a factor cache file (io/include/locus/io/
// factor_cache.hpp, a flatbuffers schema): what the requests' `save` and
// `load` fields (the CLI's --save F.locus / --load F.locus) do, for every
// command that factors. Internal to the library and its tools (C++20: spans
// and numeric factors); not installed.
//
// factor_or_load either
//  * loads the factors from `load` (refusing, with Error(BadInput), a file
//    made for another mesh (content hash), for other operators or another t,
//    for another matrix pattern, of another format version, truncated or
//    corrupted, and with Error(ResourceLimit) one larger than the memory
//    limit), or
//  * orders, analyzes and factors every requested operator (one ordering and
//    one symbolic factor, from the first matrix: all must share its pattern)
//    and, with `save`, writes them.
// Notes ("loaded 2 factor(s) from F in 0.1 s", "saved ...") go to RunContext::note.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// The two fields every factoring request has ("" = not used).
struct FactorCacheFiles {
  std::string save;  // write the factor(s) to this file after factoring
  std::string load;  // read the factor(s) from this file instead of factoring
  bool used() const { return !save.empty() || !load.empty(); }
};

// Error(BadUsage) for save and load together.
void check_factor_cache_files(const FactorCacheFiles& fc);

// One operator to factor: its label (kind, t) is stored in the file and must
// match on load; t is compared with a relative tolerance of 1e-12.
struct FactorRequest {
  std::string kind;              // "heat", "laplacian", "poisson", "deform-bilaplacian", ...
  double t = 0;                  // 0 when the operator has no time (or another scalar parameter, e.g. eps)
  const CscMatrix* A = nullptr;  // lower CSC, original vertex numbering
};

struct Factors {
  std::shared_ptr<const SymbolicFactor> symbolic;
  std::vector<NumericFactor> factors;  // one per request, in order
  bool loaded = false;
  double order_s = 0, analyze_s = 0, numeric_s = 0;  // 0 when loaded
  double load_s = 0, save_s = 0;
  double factor_s() const { return order_s + analyze_s + numeric_s; }
};

// factor_once: no caller factors again with the returned symbolic factor, so its
// assembly map is released once the factors are computed and saved
// (release_assembly_map; ~16 bytes per entry of A).
Factors factor_or_load(const FactorCacheFiles& fc, const Mesh& m, std::span<const FactorRequest> ops,
                       const RunContext& ctx, bool factor_once = false);

}  // namespace locus
