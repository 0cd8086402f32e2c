// Quality of a remeshed surface against its input (the JSON `remesh`
// object): topology (manifold, genus, components, boundary loops, from
// kernels/mesh analyze_mesh), the per-triangle smallest angles (the figure
// geogram's vorpalite and the thesis' Table 3.7.1 report) and the two-sided
// Hausdorff distance to the input relative to its bounding-box diagonal.
//
// Hausdorff between a (the input) and b (the remesh): max of (a) the distance
// from every vertex of a to b and (b) the distance from b's vertices and samples
// of every triangle of b (edge midpoints and the barycentric points (4,1,1)/6,
// (1,4,1)/6, (1,1,4)/6, (1,1,1)/3) to a; distances to triangles are exact, found
// through a uniform grid (triangle_grid.hpp). Sampled, so a lower bound of the
// true Hausdorff distance: the input, much finer than the remesh, is sampled at
// its vertices, the remesh's deviation (smooth over a triangle) at seven points.
#pragma once
#include <cstdint>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

struct RemeshStats {
  int32_t vertices = 0, faces = 0;
  bool manifold = false;
  int64_t genus = -1;          // sum over components of (2 - chi_c - b_c) / 2; -1 when not manifold
  int32_t components = 0, boundary_loops = 0;
  int64_t euler_characteristic = 0;
  double mean_min_angle_deg = 0;  // mean over triangles of the smallest angle
  double min_angle_deg = 0;
  double pct_below_30_deg = 0;    // triangles whose smallest angle is below 30 degrees, in percent
  double hausdorff_rel = -1;      // -1 when not computed
};

// Topology of any triangle mesh: manifold, genus summed over components,
// components, boundary loops (what the remesh must share with its input).
RemeshStats mesh_topology_stats(const Mesh& m);
// The same from analyze_mesh(m)'s report, already made.
RemeshStats mesh_topology_stats(const Mesh& m, const MeshReport& rep);

// Topology and angles of `remesh`, and with `hausdorff` its distance to `input`.
RemeshStats remesh_stats(const Mesh& input, const Mesh& remesh, bool hausdorff);
// The same with the distance, through the input's grid a caller already holds
// (at 416k input vertices building one costs ~0.7 s).
RemeshStats remesh_stats(const Mesh& input, const TriangleGrid& input_grid, const Mesh& remesh);

// The two-sided Hausdorff distance above (absolute): the largest distance
// from a point of either surface to the other, found by a search over each
// face that discards what cannot exceed the best found; a lower bound within
// 1% of the true distance (remesh_quality.cpp). The same on any thread count.
double hausdorff_distance(const Mesh& a, const Mesh& b);
// The same with a's grid given (ga must be TriangleGrid(a)).
double hausdorff_distance(const Mesh& a, const TriangleGrid& ga, const Mesh& b);

// The rebalance's guard (remesh_rebalance.hpp): the input's vertices to the
// remesh, the remesh's vertices and 7 fixed points of each of its triangles
// to the input (`grid`: TriangleGrid(input)). Cheaper than the search and
// blind between its samples; it only compares a round with the start, and
// the remeshes of docs/cvt.md were kept by it.
double sampled_hausdorff_distance(const Mesh& input, const TriangleGrid& grid, const Mesh& remesh);

}  // namespace locus
