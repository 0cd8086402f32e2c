// What 1:4 midpoint subdivision (mesh_generators.hpp, subdivide_midpoint)
// would make, known before anything is allocated: the face count grows as
// 4^times, so a small mesh and a large `times` ask for more faces than 32-bit
// indices hold, or more memory than the machine has. Refused up front with the
// numbers, like a factorization too large (kernels/include/locus/kernels/factor/memory_budget.hpp).
//
// The bytes counted are the subdivided mesh, the subdivision's edge table and
// the topology analysis every command runs on the result; what a command then
// builds (operators, factors) is checked where it is built, when its size is
// known (e.g. HeatGeodesic's memory check, the factorization's).
#pragma once
#include <cstdint>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

// Bytes per resulting face: the peak RSS of `locus info sphere.off --subdivide 9`
// (84M faces) was 11 GB.
inline constexpr double kSubdivisionBytesPerFace = 130.0;

struct SubdivisionEstimate {
  double faces = 0;  // faces after the subdivision (a double: 4^times overflows integers)
  double bytes = 0;  // faces * kSubdivisionBytesPerFace
};

// What `times` subdivisions of a triangle mesh of `faces` faces make.
SubdivisionEstimate estimate_subdivision(int64_t faces, int times);

// Throws before subdivide_midpoint(m, times) would allocate: Error(BadInput)
// when the result's face indices (3 per face) exceed int32, Error(ResourceLimit)
// when the estimate exceeds memory_limit_bytes(ctx); both messages name the
// mesh, the face count and the limit.
void check_subdivision(const Mesh& m, int times, const RunContext& ctx);

}  // namespace locus
