// The vertices of a remesh moved from where the surface is flat and wide to
// where it is thin (thesis §3.7.1): Lloyd spreads the sites uniformly, so a
// surface with small holes far apart or strips one input triangle wide keeps
// its holes and strips at their minimal triangulation (not cheese's limit:
// docs/cvt.md), whose triangles are as thin as the
// feature against the edge length, while its flat faces hold vertices that
// cost nothing to lose. Each round splits the longest edge of the thinnest
// triangles (remesh_split.hpp, up to 2% of the vertices), collapses as many
// edges where the remesh is flattest (remesh_collapse.hpp, CollapseOrder::Flat)
// and optimizes two rounds; a round is kept while it raises the smallest angle
// (when it is below 25 degrees) or else the mean smallest angle (below 50
// degrees), without lowering the other. Splits and collapses keep the genus,
// components and boundary loops; the vertex count stays. A remesh already at
// both targets is not touched, nor one with pinned (feature) vertices, and
// no round may raise the Hausdorff distance (sampled: vertices and 7 points
// per face) by more than 2% of its value.
#pragma once
#include <cstdint>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/remesh_optimize.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

struct RebalanceStats {
  int32_t rounds = 0;  // rounds kept
  int32_t splits = 0, collapses = 0;
  RemeshOptimizeStats optimize;
};

// `oo`: the optimization's options (its rounds are replaced by 2 per round);
// `vertex_site` (one entry per vertex, or empty) follows the vertices.
RebalanceStats rebalance_remesh(const Mesh& input, const TriangleGrid& grid, Mesh& remesh, RemeshOptimizeOptions oo,
                                std::vector<int32_t>& vertex_site, int max_rounds = 24);

}  // namespace locus
