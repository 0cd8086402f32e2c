// Sharp features of a remesh's input (thesis §3.7.1, the CVT remesh; feature
// protection as restricted-Delaunay meshers place fixed sites on creases):
// the input's feature edges are its interior edges whose dihedral angle (the
// angle between the normals of their two faces) exceeds a threshold. They
// form a graph: its corners are the vertices where one or more than two
// feature edges meet, where a curve turns by more than 45 degrees, or where
// a curve meets the boundary; its curves are the chains of feature edges
// between corners, or closed loops without one.
//
// Parts of the graph shorter in total than the remesh's mean edge are left
// out (scan noise). The remesh keeps the rest by sites on the features,
// placed after the density passes (cvt_remesh.hpp): one site at each corner and, along each curve,
// sites at equal arclength steps as close as possible to the remesh's mean
// edge (a 1-D uniform sampling; a bent curve gets more steps, at most twice
// as many, until its chords are within a tenth of the spacing of it); the
// Lloyd sites within half a mean edge of a feature go (their cells would
// straddle it), the largest cells are split for as many sites as the
// features' band lost, and a few Lloyd iterations relax the free sites
// around the feature sites (put back after each). The feature sites are
// labelled with the rest, so the cells of consecutive sites on a curve meet
// along it and the dual has an edge between them: the remesh's edges run
// along the creases, its corners on the input's. The optimization then pins the feature vertices
// (remesh_optimize.hpp, remesh_collapse.hpp, remesh_split.hpp,
// remesh_fidelity.hpp: they neither go nor leave their curve, and no edge
// between two of them flips or splits): a corner stays, a curve's vertex
// slides along its curve between its neighbors on it, as boundary vertices
// along the boundary (remesh_boundary.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/mesh.hpp"

namespace locus {

struct FeatureGraph {
  int64_t edges = 0;                         // feature edges
  std::vector<int32_t> corners;              // vertices, ascending
  std::vector<std::vector<int32_t>> curves;  // vertex chains; a closed loop repeats its first vertex last
};

// The feature graph of triangle mesh m (d derived from it) for dihedral
// angles above angle_deg (in (0, 180); BadUsage otherwise).
FeatureGraph feature_graph(const Mesh& m, const MeshDerived& d, double angle_deg);

// A feature curve and the feature sites on it, in order along it (an open
// curve's corner sites at its ends, when they were kept): the curve the
// remesh's vertices of those sites slide along (remesh_boundary.hpp).
struct FeatureCurve {
  std::vector<std::array<double, 3>> p;  // the polyline (closed: its first point not repeated)
  bool closed = false;
  std::vector<int32_t> site;             // feature site ids
  std::vector<double> s;                 // their arclengths from p[0], increasing
};

// The edges of the curves (site ids of `site`): consecutive sites, and a
// closed curve's last to its first, as (smaller, larger) pairs, sorted.
std::vector<std::pair<int32_t, int32_t>> feature_curve_edges(const std::vector<FeatureCurve>& curves);

// Drops the connected parts of g (curves sharing ends) shorter in total than
// min_length, and the corners only they ended at: isolated sharp edges of a
// scan's noise, too short for a remesh edge of their own.
void drop_short_components(const Mesh& m, FeatureGraph& g, double min_length);

// The sites on g: its corners first (where most curves end first), then per
// curve its interior samples, `spacing` apart or as near to it as a whole
// number of steps allows (a closed loop has three at least); a site closer
// than 0.4 spacing to one before it is left out (clusters of corners, short
// curves).
// With `curves`: the curves of g and their sites (ids into the result).
std::vector<SurfacePoint> feature_sites(const Mesh& m, const MeshDerived& d, const FeatureGraph& g, double spacing,
                                        std::vector<FeatureCurve>* curves = nullptr);

// Per vertex of m: the graph-geodesic (Dijkstra) distance to the nearest
// vertex of g (infinity where none is reachable).
std::vector<double> feature_distance(const Mesh& m, const MeshDerived& d, const FeatureGraph& g);

// The sites of a remesh with features: feature_sites(m, d, g, spacing)
// first, then those of `sites` farther than band * spacing from g (graph
// distance from the site's nearest corner of its face, plus the way there).
std::vector<SurfacePoint> with_feature_sites(const Mesh& m, const MeshDerived& d, const FeatureGraph& g,
                                             std::span<const SurfacePoint> sites, double spacing, double band,
                                             int32_t& feature_count, std::vector<FeatureCurve>* curves = nullptr);

// `sites` with a site more in each of the `count` largest cells (by lumped
// mass of `label`, sites from `fixed` on), at the cell's vertex farthest
// from its site: the density the feature band's removed sites leave short.
std::vector<SurfacePoint> split_largest_cells(const Mesh& m, const MeshDerived& d, std::span<const int32_t> label,
                                              std::vector<SurfacePoint> sites, int32_t count, int32_t fixed);

// The curves of `lines` with the remesh vertices of their sites in place of
// the site ids (vertex_site: per remesh vertex its site; sites without a
// vertex left out): what the optimization slides along them.
std::vector<FeatureCurve> feature_slides(const std::vector<FeatureCurve>& lines, std::span<const int32_t> vertex_site,
                                         int32_t feature_sites);

// The remesh's mean edge for `sites` vertices on area `area` (equilateral
// triangles, two per vertex).
double feature_spacing(double area, int32_t sites);

}  // namespace locus
