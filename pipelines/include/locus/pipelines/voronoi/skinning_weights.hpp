// Skinning weights from natural-neighbor coordinates (thesis §3.7.2, "Blend
// skinning"): the weight of handle j at vertex v is b_j(v), the area-stealing
// coordinate of v with respect to the handle set (pipelines/include/locus/pipelines/voronoi/natural_neighbor.hpp).
// Weights are non-negative, sum to 1 per vertex, equal the indicator at a handle,
// and are exactly 0 for handles whose cells the vertex's cell does not touch.
//
// Cost: one full heat solve per vertex (the diagram of a few handles is coarse, so
// localization does not apply, thesis §3.7.2), done 8 vertices per solve, batches
// in parallel (oneTBB flow graph, one slot per vertex: deterministic for any thread
// count), plus a re-split of the triangles each vertex's cell covers.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"

namespace locus {

struct SkinningWeights {
  int32_t handles = 0;
  std::vector<double> weight;  // n * handles, row-major (vertex v's weights at v * handles)
  int64_t degenerate = 0;      // vertices whose cell held no vertex (indicator of the containing cell)
  int64_t fallback_faces = 0;  // summed over vertices
  double max_clamped = 0;      // largest relative negative area difference clamped to 0
  double prepare_s = 0, weights_s = 0;
};

// H: prepared heat operator of m; handles: at least one, valid surface points.
SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> handles,
                                 const RunContext& ctx);

}  // namespace locus
