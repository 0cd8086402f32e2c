// Saving and loading factors (issue 9 item 3; DESIGN.md "Engine API": factor
// cache). A file holds one symbolic + numeric factor, the locus format
// version, and the content hash of the mesh and the operator it was made for.
// Loading refuses, with Error(BadInput) naming the file and the reason: other
// format versions, another mesh, truncated or corrupted files (per-section
// checksums), and structurally invalid contents (every index checked), so a
// loaded factor can never make a solve read out of bounds.
#pragma once
#include <cstdint>
#include <string>

#include "kernels/supernodal_factor.hpp"
#include "locus/mesh.hpp"

namespace locus {

constexpr uint32_t kFactorCacheFormat = 1;

struct FactorCacheInfo {
  uint64_t mesh_hash = 0;
  std::string operator_kind;
  double t = 0;
};

// Content hash of a mesh: positions (bitwise) and faces.
uint64_t mesh_content_hash(const Mesh& m);

void save_factor(const std::string& path, const NumericFactor& f, const FactorCacheInfo& info);
// Loads and verifies; if expected_mesh_hash != 0 it must match the file's.
NumericFactor load_factor(const std::string& path, FactorCacheInfo& info, uint64_t expected_mesh_hash = 0);

}  // namespace locus
