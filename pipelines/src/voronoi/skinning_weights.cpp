// Skinning weights from natural-neighbor coordinates (pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp;
// thesis §3.7.2).
#include "locus/pipelines/voronoi/skinning_weights.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <memory>

#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"

namespace locus {

namespace {

struct SkinMsg {
  int32_t first = 0;
  int lanes = 0;
  NaturalCoordinates c[kLanes];
};

struct SkinScratch {
  HeatBatch batch;
  std::vector<double> lane;
};

}  // namespace

SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> handles,
                                 const RunContext& ctx) {
  BatchStopwatch sw;
  const NaturalNeighborField F = prepare_natural_neighbors(H, m, handles, ctx);
  SkinningWeights W;
  W.prepare_s = sw.lap();
  const int32_t n = m.num_vertices();
  const int32_t k = static_cast<int32_t>(handles.size());
  W.handles = k;
  W.weight.assign(static_cast<size_t>(n) * k, 0.0);
  const int32_t nb = (n + kLanes - 1) / kLanes;
  tbb::enumerable_thread_specific<SkinScratch> scratch;
  auto solve_batch = [&](int32_t b) {
    SkinScratch& s = scratch.local();
    auto msg = std::make_shared<SkinMsg>();
    msg->first = b * kLanes;
    msg->lanes = std::min(kLanes, n - msg->first);
    s.batch.clear_sources();
    s.batch.kept.clear();
    for (int l = 0; l < msg->lanes; ++l) {
      const int32_t v = msg->first + l;
      const double one = 1.0;
      s.batch.add_source({&v, 1}, {&one, 1});
    }
    solve_heat_batch(H, s.batch);
    s.lane.resize(n);
    for (int l = 0; l < msg->lanes; ++l) {
      for (int32_t v = 0; v < n; ++v) s.lane[v] = s.batch.values[static_cast<size_t>(v) * kLanes + l];
      msg->c[l] = natural_neighbor_coordinates(F, m, vertex_point(msg->first + l), s.lane);
    }
    return msg;
  };
  auto store = [&](const std::shared_ptr<SkinMsg>& msg) {  // per-vertex slots: arrival order is irrelevant
    for (int l = 0; l < msg->lanes; ++l) {
      const NaturalCoordinates& c = msg->c[l];
      std::copy(c.weight.begin(), c.weight.end(), W.weight.begin() + static_cast<size_t>(msg->first + l) * k);
      W.degenerate += c.degenerate;  // integer sums and a max: independent of arrival order
      W.fallback_faces += c.fallback_faces;
      W.max_clamped = std::max(W.max_clamped, c.clamped);
    }
  };
  run_batch_graph<SkinMsg>(ctx, nb, solve_batch, store, "skinning weights");
  W.weights_s = sw.lap();
  return W;
}

}  // namespace locus
