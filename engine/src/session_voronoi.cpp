// Session queries of the heat-diffusion diagrams (thesis §3.4,
// §3.7.2): Voronoi diagram with its bisector polylines, natural-neighbor
// coordinates (a prepared field and one-shot) and skinning weights.
//
// Each is the pipeline the CLI runs (`locus voronoi|nncoords|skinweights`) on
// the Session's cached factor of M - tL (session_heat.cpp, diffusion()), so a
// later query with the same t factors nothing.
#include <algorithm>
#include <string>

#include "field_copy.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/pipelines/voronoi/natural_neighbor.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {

using namespace session_detail;

// The prepared field keeps what it points into alive: the State (its mesh) and the heat factor.
struct NaturalNeighbors::Impl {
  std::shared_ptr<State> state;
  std::shared_ptr<const HeatDiffusion> heat;
  NaturalNeighborField field;
};

NaturalNeighbors::NaturalNeighbors() = default;
NaturalNeighbors::~NaturalNeighbors() = default;
NaturalNeighbors::NaturalNeighbors(NaturalNeighbors&&) noexcept = default;
NaturalNeighbors& NaturalNeighbors::operator=(NaturalNeighbors&&) noexcept = default;
NaturalNeighbors::NaturalNeighbors(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

int32_t NaturalNeighbors::num_sites() const { return impl_ ? static_cast<int32_t>(impl_->field.sites.size()) : 0; }

NaturalNeighborResult NaturalNeighbors::coordinates(const MeshPoint& q) const {
  if (!impl_) fail(ErrorCode::BadUsage, "natural neighbors: the field is empty (moved from or default-constructed)");
  const SurfacePoint p = surface_point(*impl_->state, q, "natural neighbors: point", 0);
  const NaturalCoordinates c = natural_neighbor_coordinates(impl_->field, impl_->state->mesh, p);
  NaturalNeighborResult r;
  LOCUS_COPY_FIELDS(r, c, weight, cell_area, at_site, degenerate);
  return r;
}

std::vector<MeshPoint> Session::random_points(int32_t count, uint64_t seed) const {
  const std::shared_ptr<State> s = impl_->current();
  if (count < 0) fail(ErrorCode::BadUsage, "random_points: count must be >= 0, got " + std::to_string(count));
  std::vector<MeshPoint> out;
  for (const SurfacePoint& p : random_surface_points(s->mesh, count, seed))
    out.push_back(MeshPoint::in_face(p.face, p.bary[0], p.bary[1], p.bary[2]));
  return out;
}

VoronoiResult Session::voronoi(ConstView<MeshPoint> generators, const HeatQuery& q,
                               const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (generators.empty() || generators.size() > static_cast<size_t>(impl_->nv))
    fail(ErrorCode::BadUsage, "voronoi: the number of generators must be in 1.." + std::to_string(impl_->nv) +
                                  " (the vertex count), got " + std::to_string(generators.size()));
  const std::vector<SurfacePoint> sites = surface_points(*s, generators, "voronoi: generator");
  const CallProgress progress(ctx, !diffusion_cached(*s, q));
  const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, q, progress.build());
  ctx.check_cancel();
  const HeatVoronoi V = heat_voronoi(*H, s->mesh, sites, {}, {}, progress.query().sub(0.0, 0.8));
  const VoronoiDiagram D = extract_voronoi_diagram(*H, s->mesh, sites, V, progress.query().sub(0.8, 1.0));
  VoronoiResult r;
  r.label.assign(V.label.begin(), V.label.end());
  r.points = D.points;
  r.line_offsets.push_back(0);
  for (const std::vector<int32_t>& line : D.polylines) {
    r.line_points.insert(r.line_points.end(), line.begin(), line.end());
    r.line_offsets.push_back(static_cast<int32_t>(r.line_points.size()));
  }
  r.corners = D.corners;
  std::vector<int64_t> cell(generators.size(), 0);
  for (int32_t l : V.label) ++cell[l];
  r.empty_cells = std::count(cell.begin(), cell.end(), 0);
  for (int32_t v = 0; v < impl_->nv; ++v) r.vertices_without_heat += !(V.top_value[static_cast<size_t>(v) * kVoronoiTopK] > 0);
  progress.finish("voronoi");
  return r;
}

NaturalNeighbors Session::prepare_natural_neighbors(ConstView<MeshPoint> sites, const HeatQuery& q,
                                                    const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (sites.empty()) fail(ErrorCode::BadUsage, "natural neighbors: no site given");
  const std::vector<SurfacePoint> pts = surface_points(*s, sites, "natural neighbors: site");
  auto impl = std::make_shared<NaturalNeighbors::Impl>();
  impl->state = s;
  const CallProgress progress(ctx, !diffusion_cached(*s, q));
  impl->heat = diffusion(*s, q, progress.build());
  ctx.check_cancel();
  impl->field = locus::prepare_natural_neighbors(*impl->heat, s->mesh, pts, progress.query());
  progress.finish("natural neighbors");
  return NaturalNeighbors(std::move(impl));
}

NaturalNeighborResult Session::natural_neighbor_coordinates(ConstView<MeshPoint> sites, const MeshPoint& point,
                                                            const HeatQuery& q, const RunContext& ctx) const {
  {
    const std::shared_ptr<State> s = impl_->current();
    surface_point(*s, point, "natural neighbors: point", 0);  // a bad point fails before the diagram is computed
  }
  return prepare_natural_neighbors(sites, q, ctx).coordinates(point);
}

SkinningWeightsResult Session::skinning_weights(ConstView<MeshPoint> handles, const HeatQuery& q,
                                                const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (handles.empty()) fail(ErrorCode::BadUsage, "skinning_weights: no handle given");
  const std::vector<SurfacePoint> pts = surface_points(*s, handles, "skinning_weights: handle");
  const CallProgress progress(ctx, !diffusion_cached(*s, q));
  const std::shared_ptr<const HeatDiffusion> H = diffusion(*s, q, progress.build());
  ctx.check_cancel();
  const SkinningWeights W = locus::skinning_weights(*H, s->mesh, pts, progress.query());
  SkinningWeightsResult r;
  r.weight = W.weight;
  r.degenerate_vertices = W.degenerate;
  LOCUS_COPY_FIELDS(r, W, handles, fallback_faces, max_clamped);
  progress.finish("skinning weights");
  return r;
}

}  // namespace locus
