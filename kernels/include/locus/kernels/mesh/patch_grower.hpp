// The one patch grower: which vertices of a mesh make up a region around a
// center (or around a few seed vertices), and the region as a mesh of its own.
//
// Two modes, one loop each, both deterministic:
//
//   Rings     breadth-first search on the vertex-edge graph (thesis §4.4: "We
//             generate patches ... using BFS on the vertex-edge graph of the
//             triangle mesh"). Seeds first, then ring by ring; the neighbors of
//             a vertex in ascending id order. Stops once max_vertices are taken
//             (the last ring may be partial) or the seeds' components are
//             exhausted.
//   Geodesic  Dijkstra on edge lengths |x_j - x_i| (a geodesic disk in the graph
//             metric). Vertices are taken when they settle, in order of graph
//             distance; a binary min-heap with decrease-key through a position
//             array decides ties (the heap of DemLogMap, operation for
//             operation, so the order is the DEM's). Stops at max_vertices, at
//             max_radius (RadiusRule), or when the seeds' components are
//             exhausted.
//
// Which caller uses which mode, and why (each reproduces the grower it replaced,
// vertex for vertex and in the same order):
//   - parameterization (pipelines/param patch_param, patch_param_circle) and
//     deformation ROIs (pipelines/deform): Rings. The thesis defines these
//     patches by BFS; a ring count is what the Neumann and ROI experiments are
//     stated in, and BFS needs no edge lengths.
//   - log maps and local geodesic distances (Session::logmap, CLI logmap and
//     geodesic --fraction, benches): Geodesic with max_vertices = the patch
//     size. A log map is radial, so its patch should be a disk in distance, not
//     in hops (on anisotropic triangulations a BFS patch is elongated).
//   - CVT first neighborhoods (pipelines/voronoi site_neighborhoods): Geodesic
//     from the site's face corners (seed distance = |corner - site|), RadiusRule::
//     PruneBeyond at the expected cell radius, no vertex limit; the caller sorts
//     the vertices. A cell is a metric ball, so its neighborhood is one too.
//     Or the sites' first cells: label_nearest_seeds from every site's corners.
//
// Prepare once per mesh (adjacency, edge lengths, vertex-to-face incidence),
// then grow any number of patches with a caller-owned workspace: a query costs
// O(patch size) (times log for Geodesic) plus the faces around it, never O(mesh)
// once the workspace has grown. The vertex selection also runs on a bare
// Adjacency (grow_vertices), for callers that hold no mesh.
//
// The patch's faces (grow_patch, extract_patch) are the mesh faces whose corners
// were all selected, less "ears": a vertex with a single patch face is the tip
// of a spike of the partial last ring (the face has all three corners on the
// boundary); it is dropped with its face, repeatedly, because such spikes are
// not part of a disk-like region and fold over under Neumann data (measured: one
// flipped ear in every 10% patch of a level-4 icosphere). Vertices that end up
// in no patch face are dropped too, so the patch has no isolated vertices and
// may hold slightly fewer vertices than were selected.
//
// Thread safety: a prepared grower is const; one workspace per thread.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

enum class GrowMode : uint8_t {
  Rings,     // BFS on the vertex-edge graph
  Geodesic,  // Dijkstra on edge lengths
};

// How max_radius stops a Geodesic grow (unused with an infinite radius).
enum class RadiusRule : uint8_t {
  // Every reached vertex is queued; growing stops when the nearest queued
  // vertex is farther than max_radius (DemLogMap's rule).
  StopBeyond,
  // A vertex is queued only at distance <= max_radius; seeds are taken whatever
  // their distance (the rule of the CVT's neighborhoods). The same vertex set as
  // StopBeyond plus the far seeds; ties may settle in another order.
  PruneBeyond,
};

struct GrowOptions {
  GrowMode mode = GrowMode::Rings;
  int32_t max_vertices = std::numeric_limits<int32_t>::max();  // >= 1
  double max_radius = std::numeric_limits<double>::infinity();  // Geodesic only; >= 0
  RadiusRule radius_rule = RadiusRule::StopBeyond;
};

// A start vertex of a grow. `distance`: its initial graph distance (Geodesic;
// Rings puts every seed in ring 0). A repeated seed keeps its smallest distance.
struct GrowSeed {
  int32_t vertex = -1;
  double distance = 0.0;
};

// Scratch of the vertex selection: n-sized arrays reset only where a grow
// touched them (dist +inf, state 0 between calls).
struct GrowWorkspace {
  HostVector<double> dist;      // Geodesic: tentative distance
  HostVector<int32_t> level;    // Rings: BFS depth; Geodesic: heap position
  HostVector<uint8_t> state;    // 0 unseen, 1 queued, 2 taken
  HostVector<int32_t> heap;     // Geodesic: binary min-heap of queued vertices (by dist)
  HostVector<int32_t> touched;  // vertices whose state is not 0
};

// Selects the vertices of a grow into `out` (cleared first), in the order taken
// (seeds first). edge_length: one entry per adjacency entry (|x_j - x_i| for
// neighbor j of vertex i), needed by Geodesic only. Returns the BFS depth
// reached (Rings; the last ring may be partial), 0 for Geodesic. BadUsage for
// a seed out of range, no seed, max_vertices < 1, a negative or NaN radius, or
// Geodesic without edge lengths.
int32_t grow_vertices(const Adjacency& adj, std::span<const double> edge_length, std::span<const GrowSeed> seeds,
                      const GrowOptions& opt, GrowWorkspace& ws, HostVector<int32_t>& out);
// A Geodesic grow (opt.mode is ignored) whose edge lengths come from m's
// positions as the grow reaches them, the values of adjacency_edge_lengths bit
// for bit: a few grows on a large mesh without its mesh-wide array.
void grow_geodesic_vertices(const Adjacency& adj, const Mesh& m, std::span<const GrowSeed> seeds,
                            const GrowOptions& opt, GrowWorkspace& ws, HostVector<int32_t>& out);
// The same into a std::vector (tools and tests; a copy of the grown vertices).
inline int32_t grow_vertices(const Adjacency& adj, std::span<const double> edge_length, std::span<const GrowSeed> seeds,
                             const GrowOptions& opt, GrowWorkspace& ws, std::vector<int32_t>& out) {
  HostVector<int32_t> grown;
  const int32_t depth = grow_vertices(adj, edge_length, seeds, opt, ws, grown);
  out.assign(grown.begin(), grown.end());
  return depth;
}

// Graph-geodesic Voronoi labels: one Dijkstra from all seeds at once (the
// Geodesic loop above, without limits); label[v] = seed_label[k] of the seed k
// whose path to v is shortest. A vertex changes label only for a strictly
// shorter path, so ties keep the label that reached it first (seeds in the given
// order, then the heap's settle order): deterministic. -1 where no seed reaches
// (another component). No seeds: all -1. BadUsage on a seed out of range, or
// sizes that do not match (one label per vertex, one per seed, one edge length
// per adjacency entry).
void label_nearest_seeds(const Adjacency& adj, std::span<const double> edge_length, std::span<const GrowSeed> seeds,
                         std::span<const int32_t> seed_label, GrowWorkspace& ws, std::span<int32_t> label);

// The same with the edge lengths of m's positions computed as the Dijkstra
// reaches them (adjacency_edge_lengths' values, bit for bit): no mesh-wide
// array (20 MB at 416k vertices) for a caller that labels a few times.
void label_nearest_seeds_by_positions(const Adjacency& adj, const Mesh& m, std::span<const GrowSeed> seeds,
                                      std::span<const int32_t> seed_label, GrowWorkspace& ws, std::span<int32_t> label);

// Edge lengths per adjacency entry of a mesh (the input of Geodesic):
// sqrt of the summed squared coordinate differences, neighbor minus vertex.
HostVector<double> adjacency_edge_lengths(const Mesh& m, const Adjacency& adj);
// One of them: |x_j - x_i| for neighbor j of vertex i (the coordinate
// differences neighbor minus vertex, squared, summed x, y, z), the length
// every grow and seed labelling on a mesh's positions reads, bit for bit.
inline double adjacency_edge_length(const Mesh& m, int32_t i, int32_t j) {
  return std::sqrt((m.x[j] - m.x[i]) * (m.x[j] - m.x[i]) + (m.y[j] - m.y[i]) * (m.y[j] - m.y[i]) +
                   (m.z[j] - m.z[i]) * (m.z[j] - m.z[i]));
}

// Rings from one seed, without a workspace (allocates n bytes per call): the
// first `count` vertices of the BFS from `seed` (count <= 1 gives the seed).
std::vector<int32_t> grow_ring_vertices(const Adjacency& adj, int32_t seed, int32_t count);

// Everything patch growing needs of a mesh, computed once. Holds a pointer to
// the mesh: the mesh must outlive it and stay unchanged.
struct PatchGrower {
  const Mesh* mesh = nullptr;
  Adjacency adjacency;
  HostVector<double> edge_length;  // per adjacency entry: |x_j - x_i| for neighbor j of vertex i
  HostVector<int64_t> vf_offsets;  // nv + 1: faces incident to each vertex (CSR)
  HostVector<int32_t> vf_faces;    //   ascending face ids
};

// Throws BadInput unless `m` is a valid triangle mesh (mesh_topology checks).
// Coordinates are not checked (Rings does not read them); Geodesic needs
// finite ones, which the callers' own mesh checks (and the readers) ensure.
PatchGrower prepare_patch_grower(const Mesh& m);
// The same from an adjacency already built for m (vertex_adjacency(m)), copied.
PatchGrower prepare_patch_grower(const Mesh& m, const Adjacency& adjacency);

// Per-thread scratch of patch growing.
struct PatchWorkspace {
  HostVector<int32_t> local;  // nv: local index of a global vertex during a call; all -1 between calls
  GrowWorkspace grow;
};

struct MeshPatch {
  std::vector<int32_t> vertices;  // global ids of the patch vertices, in the order grown (center first)
  std::vector<int32_t> faces;     // global ids of the patch faces, ascending
  Mesh mesh;                      // the patch as a mesh: vertex k is vertices[k], face k is faces[k]
  int32_t rings = 0;              // Rings: BFS depth reached (the last ring may be partial); Geodesic: 0
};

// Number of patch vertices for a fraction of the mesh: round(fraction * nv),
// at least 1. Throws BadUsage unless 0 < fraction <= 1.
int32_t patch_vertex_count(int32_t nv, double fraction);

// The vertices only: grow_vertices on the grower's adjacency and edge lengths
// from one center. Uses ws.grow; returns the BFS depth (Rings) or 0.
int32_t grow_patch_vertices(const PatchGrower& g, int32_t center, const GrowOptions& opt, PatchWorkspace& ws,
                            HostVector<int32_t>& out);
// The same into a std::vector (tools and tests; a copy of the grown vertices).
inline int32_t grow_patch_vertices(const PatchGrower& g, int32_t center, const GrowOptions& opt, PatchWorkspace& ws,
                                   std::vector<int32_t>& out) {
  HostVector<int32_t> grown;
  const int32_t depth = grow_patch_vertices(g, center, opt, ws, grown);
  out.assign(grown.begin(), grown.end());
  return depth;
}

// Grows the patch around `center` (BadUsage if the center is out of range or
// opt.max_vertices < 1; a count above the center's component size stops at the
// whole component) and assembles it as a mesh.
MeshPatch grow_patch(const PatchGrower& g, int32_t center, const GrowOptions& opt, PatchWorkspace& ws);

// The patch spanned by a given vertex set: faces with all corners in the set,
// vertices of those faces in the given order. Same result type, rings = 0.
MeshPatch extract_patch(const PatchGrower& g, std::span<const int32_t> vertices, PatchWorkspace& ws);

// Options of the callers (see the table above).
inline GrowOptions ring_patch(int32_t count) { return {GrowMode::Rings, count}; }
inline GrowOptions geodesic_disk(int32_t count) { return {GrowMode::Geodesic, count}; }

}  // namespace locus
