// The heat operator M - tL of a command that factors its own (voronoi, cvt):
// built on the mesh, then factored or loaded through the factor cache
// (engine/include/locus/engine/factor_store.hpp) under the label "heat" with
// the resolved t, so a file of `locus factor --matrix heat`, `voronoi` or
// `cvt` with the same t and mesh loads in any of them. Internal to the engine.
#pragma once
#include <functional>

#include "locus/engine/factor_store.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

// M - tL of `mesh` (t resolved on its mean edge length), factored or loaded:
// the cotan operator's, or with `robust` the robust operator's Laplacian and
// mass (operator_choice.hpp), the mesh then checked only for triangles and
// finite coordinates. `cache` reports the files used. factor_once: the caller
// only solves with the factor, never factors again with its symbolic part
// (factor_or_load's factor_once). `derived` (the mesh's, when the caller
// holds it) gives the check already made, h, the mass and the edge incidence
// the cotan operator is assembled on, the same values bit for bit without
// three more edge incidences (45 MB each at 416k vertices) freed just before
// the factor is allocated. `assembled`, when given, is called once the
// operator is assembled and before it is ordered and factored: nothing of
// `derived` is read after it but its mass, h and checks (the cvt command frees
// the incidence there). `borrow_mass`: the cotan operator's mass is left
// empty when it would be a copy of derived->mass (LloydOptions::prepared reads
// derived->mass then; 3.3 MB at 416k vertices); the caller keeps `derived`.
HeatDiffusion command_heat_operator(const Mesh& mesh, bool robust, const HeatTime& time,
                                   const FactorCacheFiles& files, const RunContext& ctx, FactorCacheReport& cache,
                                   bool factor_once = false, const MeshDerived* derived = nullptr,
                                   const std::function<void()>& assembled = {}, bool borrow_mass = false);

}  // namespace locus
