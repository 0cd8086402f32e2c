// Edge flips of a remesh on its input (thesis §3.7.1; the flip side of
// remesh_optimize.hpp): Delaunay or valence flips that keep the surface, its
// creases and its feature curves. Internal to pipelines/src/voronoi.
#pragma once
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/remesh_boundary.hpp"
#include "locus/pipelines/voronoi/remesh_features.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

// The edges that never flip: the feature curves' own (feature_curve_edges),
// split where a vertex joins a curve. An edge between two feature vertices
// that skips one is no feature edge: three vertices on a straight crease
// would otherwise keep a 0-degree triangle. Without curves (pinned vertices
// only), every edge between two pinned vertices.
class FeatureEdges {
 public:
  FeatureEdges(const std::vector<FeatureCurve>& slides, const std::vector<uint8_t>& pinned);
  bool kept(int32_t u, int32_t w) const;
  bool by_curves() const { return !edges_.empty(); }
  void split(int32_t a, int32_t b, int32_t c);  // a-b becomes a-c and c-b

 private:
  std::vector<std::pair<int32_t, int32_t>> edges_;  // sorted (smaller, larger)
  const std::vector<uint8_t>& pinned_;
};

struct FlipContext {
  const Mesh& input;
  const TriangleGrid& grid;
  FeatureEdges& features;
  std::vector<uint8_t>& fixed;  // per remesh vertex: boundary or pinned; a vertex joining a curve too
  BoundaryCurves& curves;
};

// One sweep of flips over the edges in sorted order (F: the remesh's
// triangles, updated with valence): by_valence towards the target valences
// (without dropping an angle below 20 degrees), else Delaunay (the flip raises
// the pair's smallest angle); never across a crease of the remesh (unless the
// flip opens a fold) nor a feature edge, unless a free vertex lies on it (its
// angle there above 170 degrees: a vertex projected onto a convex crease, where
// no tangential move takes it off): the vertex joins the curve
// (BoundaryCurves::adopt) and the edge flips. Returns the number of flips.
int64_t flip_pass(const FlipContext& fc, Mesh& m, std::vector<std::array<int32_t, 3>>& F,
                  std::vector<int32_t>& valence, const std::vector<int32_t>& target, bool by_valence);

}  // namespace locus
