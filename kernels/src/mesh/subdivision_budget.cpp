// The size of a 1:4 midpoint subdivision before it is made (kernels/include/locus/kernels/mesh/subdivision_budget.hpp).
#include "locus/kernels/mesh/subdivision_budget.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

std::string count_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, v < 1e15 ? "%.0f" : "%.3g", v);
  return buf;
}

std::string gib(double bytes) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return buf;
}

}  // namespace

SubdivisionEstimate estimate_subdivision(int64_t faces, int times) {
  SubdivisionEstimate e;
  e.faces = static_cast<double>(faces) * std::pow(4.0, times);
  e.bytes = e.faces * kSubdivisionBytesPerFace;
  return e;
}

void check_subdivision(const Mesh& m, int times, const RunContext& ctx) {
  if (times <= 0) return;
  const SubdivisionEstimate e = estimate_subdivision(m.num_faces(), times);
  const std::string what = mesh_name(m) + ": " + std::to_string(times) + " midpoint subdivision" +
                           (times == 1 ? "" : "s") + " of its " + std::to_string(m.num_faces()) +
                           " faces would make " + count_text(e.faces) + " faces";
  // Faces are indexed by int32 offsets, 3 per triangle.
  constexpr double kMaxFaces = std::numeric_limits<int32_t>::max() / 3;
  if (e.faces > kMaxFaces)
    fail(ErrorCode::BadInput, what + ", more than the " + count_text(kMaxFaces) + " that 32-bit indices hold");
  const double limit = static_cast<double>(memory_limit_bytes(ctx));
  if (e.bytes > limit)
    fail(ErrorCode::ResourceLimit,
         what + " and need about " + gib(e.bytes) + " for them and the data derived from them, more than " +
             (ctx.max_memory_bytes > 0 ? "the memory limit of " + gib(limit)
                                       : "the default memory limit of " + gib(limit) + " (80% of physical memory)") +
             "; raise it with --max-memory (RunContext::max_memory_bytes) or subdivide less");
}

}  // namespace locus
