// Saving and loading factors (DESIGN.md "Engine API": factor cache). A file holds one symbolic factor and one or more numeric factors on
// it (e.g. M - t L_C for several t, or the heat and Poisson operators of the
// heat method), each labelled with an operator kind and t, plus the locus
// format version and the content hash of the mesh they were made for.
// Loading refuses, with Error(BadInput) naming the file and the reason: other
// format versions, another mesh, truncated or corrupted files (per-section
// checksums), and structurally invalid contents (every index checked), so a
// loaded factor can never make a solve read out of bounds. Whether the stored
// operators are the ones the caller wants (kind, t) is the caller's check:
// see tools/cli/cli_common.hpp (factor_or_load) for the CLI's.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/mesh.hpp"

namespace locus {

constexpr uint32_t kFactorCacheFormat = 1;

struct FactorCacheInfo {
  uint64_t mesh_hash = 0;
  std::string operator_kind;
  double t = 0;
};

// Content hash of a mesh: positions (bitwise) and faces. Never 0.
uint64_t mesh_content_hash(const Mesh& m);

// One factor to save: every entry of a file shares the same symbolic factor.
struct FactorEntry {
  std::string operator_kind;  // "heat", "laplacian", "poisson", ... (free text, compared by the caller)
  double t = 0;               // diffusion time, 0 when the operator has none
  const NumericFactor* factor = nullptr;
};

// What a file holds, after every check passed.
struct LoadedFactors {
  uint64_t mesh_hash = 0;
  std::vector<std::string> operator_kinds;  // one per factor, in saved order
  std::vector<double> t;
  std::vector<NumericFactor> factors;       // all share one symbolic factor
};

// Writes atomically (temporary file + rename). Error(BadUsage) for no entries,
// an empty factor, or entries on different symbolic factors; Error(BadInput)
// when the file cannot be written.
void save_factors(const std::string& path, uint64_t mesh_hash, std::span<const FactorEntry> entries);
// Loads and verifies; if expected_mesh_hash != 0 it must match the file's.
LoadedFactors load_factors(const std::string& path, uint64_t expected_mesh_hash = 0);

// Single-factor forms of the two above.
void save_factor(const std::string& path, const NumericFactor& f, const FactorCacheInfo& info);
NumericFactor load_factor(const std::string& path, FactorCacheInfo& info, uint64_t expected_mesh_hash = 0);

}  // namespace locus
