// `skinweights` as every front end runs it (engine/include/locus/engine/
// skinning_requests.hpp): handles checked and resolved to vertex sets
// (pipelines/.../skinning_handles.hpp), the Session's cached factor of M - tL,
// then the sampled or exact natural-neighbor skinning weights (thesis §3.7.2;
// pipelines/.../skinning_weights.hpp).
#include <chrono>
#include <optional>
#include <string>

#include "field_copy.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/skinning_requests.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/skinning_coarse.hpp"
#include "locus/pipelines/voronoi/skinning_handles.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

namespace {

// The request's handles and bones as pipeline handles, ids and sizes checked.
std::vector<SkinningHandle> request_handles(const SkinningRequest& req, int32_t n) {
  std::vector<SkinningHandle> hs;
  for (size_t i = 0; i < req.handles.size(); ++i) {
    const std::string name = "skinning: handle " + std::to_string(i);
    if (req.handles[i].empty()) fail(ErrorCode::BadUsage, name + " has no vertex");
    SkinningHandle h;
    for (int64_t v : req.handles[i]) {
      if (v < 0 || v >= n)
        fail(ErrorCode::BadUsage, name + ": vertex " + std::to_string(v) + " out of range (the mesh has " +
                                      std::to_string(n) + " vertices)");
      h.vertices.push_back(static_cast<int32_t>(v));
    }
    hs.push_back(std::move(h));
  }
  for (size_t i = 0; i < req.bone.size(); ++i) {
    const std::vector<double>& b = req.bone[i];
    if (b.size() < 6 || b.size() % 3 != 0)
      fail(ErrorCode::BadUsage, "skinning: bone " + std::to_string(i) +
                                    " needs x,y,z of at least 2 points (got " + std::to_string(b.size()) + " numbers)");
    SkinningHandle h;
    for (size_t p = 0; p < b.size(); p += 3) h.bone.push_back({b[p], b[p + 1], b[p + 2]});
    hs.push_back(std::move(h));
  }
  if (hs.empty()) fail(ErrorCode::BadUsage, "skinning: no handle given");
  return hs;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

SkinningReport Session::skinning(const SkinningRequest& req, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  const Mesh& m = s->mesh;
  if (req.samples < 0) fail(ErrorCode::BadUsage, "skinning: samples must be >= 0 (got " + std::to_string(req.samples) + ")");
  const std::vector<std::vector<int32_t>> sets = handle_vertex_sets(m, request_handles(req, m.num_vertices()));
  const HeatTime time = heat_time_of(req.t, std::nullopt, HeatTime{1.0, true});
  HeatQuery q;
  if (time.times_h2) {
    q.t_factor = time.value;
  } else {
    q.t = time.value;
  }
  SkinningOptions o;
  o.method = req.exact ? SkinningMethod::Exact : SkinningMethod::Sampled;
  o.samples = req.samples;
  SkinningReport r;
  SkinningWeights W;
  bool coarse = !s->robust && skinning_uses_coarse_level(m.num_vertices(), o);
  if (coarse) {
    // A large clean mesh: weights on a coarse level with its own operator, the
    // fine mesh's is neither needed nor built (pipelines/.../skinning_coarse.hpp).
    // Where no manifold coarse level comes out (or its operator fails), the
    // fine sampled method runs instead.
    try {
      const CallProgress progress(ctx, false);
      W = skinning_weights_coarse(m, sets, o, q.t > 0 ? 0.0 : diffusion_t_factor(q), q.t, progress.query());
      r.factor_s = W.factor_s;
      r.t = W.t;
      progress.finish("skinning weights");
    } catch (const Error& e) {
      if (e.code() == ErrorCode::Cancelled) throw;
      coarse = false;
    }
  }
  if (!coarse) {
    const CallProgress progress(ctx, !diffusion_cached(*s, q));
    const auto t0 = std::chrono::steady_clock::now();
    const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, q, progress.build());
    r.factor_s = since(t0);
    ctx.check_cancel();
    W = locus::skinning_weights(*H, m, sets, o, progress.query());
    r.t = H->t;
    progress.finish("skinning weights");
  }
  r.weight = W.weight;
  r.handle_vertices = sets;
  r.method = W.method;
  r.degenerate_vertices = W.degenerate;
  LOCUS_COPY_FIELDS(r, W, handles, samples, sample_rings, radius, fallback_faces, max_clamped, coarse_vertices,
                    prepare_s, weights_s, propagate_s);
  return r;
}

}  // namespace locus
