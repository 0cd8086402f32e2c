// Discrete exponential map (DEM) by Dijkstra propagation — the baseline of
// thesis §6.7 (Schmidt, Grimm & Wyvill 2006, with the neighbor averaging of
// Schmidt 2010). Patches for other methods come from the patch grower
// (kernels/include/locus/kernels/mesh/patch_grower.hpp, Geodesic mode), which
// selects the same vertices in the same order as query() does here.
//
// Dijkstra from the center c over edge lengths finalizes vertices in order of
// graph distance. Each vertex carries a tangent frame (n, e1, e2 = n x e1): the
// center's is (n_c, its lowest-numbered neighbor's edge projected, n_c x e1); a
// newly finalized vertex q takes its Dijkstra parent's frame rotated by the
// minimal rotation that maps the parent's normal onto n_q (discrete parallel
// transport along the shortest path). Its normal coordinates are the average,
// over every already finalized neighbor r, of u(r) + log_r(q), where log_r(q) is
// the edge q - r projected into r's tangent plane, rescaled to the edge length
// and written in r's frame; the weights are 1 / |q - r| (upwind averaging: the
// average over several predecessors damps the error of any single path).
// Normals are the area-weighted vertex normals (kernels/include/locus/kernels/mesh/mesh_operators.hpp).
//
// Implementation: flat arrays only (CSR adjacency with per-entry edge lengths,
// positions, normals); a binary heap with decrease-key through a position
// array; a caller-owned workspace whose n-sized arrays are reset only at the
// entries a query touched, so a query costs O(k log k) for k visited vertices
// and never allocates once the workspace has grown.
//
// Thread safety: const after construction; one DemWorkspace per thread.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

// Where a vertex is in the Dijkstra propagation.
enum class DemVertexState : uint8_t { Unseen, Queued, Finalized };

struct DemWorkspace {
  std::vector<double> dist;     // n, +inf between queries
  std::vector<DemVertexState> state;  // n: Unseen between queries
  std::vector<int32_t> parent;  // n
  std::vector<int32_t> heap_pos;
  std::vector<double> u, v;     // n: map coordinates of finalized vertices
  std::vector<double> e1;       // 3n: frame of finalized vertices
  std::vector<int32_t> heap;    // binary min-heap of queued vertices (by dist)
  std::vector<int32_t> touched; // vertices whose state is not 0
};

class DemLogMap {
 public:
  // Needs a triangle mesh (Error(BadInput) otherwise) with finite positions.
  explicit DemLogMap(const Mesh& m);

  int32_t num_vertices() const { return static_cast<int32_t>(x_.size()); }

  // Grows the Dijkstra disk around `center` until `count` vertices are
  // finalized, the next one is farther than `max_radius` (graph distance), or
  // the component is exhausted. Writes the vertices in the order finalized
  // (center first) to patch[0..k) and returns k. With u and v non-empty (at least
  // `count` entries each) also computes the DEM coordinates of those vertices;
  // with empty u, v it only selects the patch (a geodesic disk in graph metric:
  // grow_patch_vertices with geodesic_disk(count) picks the same vertices).
  // patch must have at least `count` entries; count >= 1.
  int32_t query(int32_t center, int32_t count, double max_radius, std::span<int32_t> patch, std::span<double> u,
                std::span<double> v, DemWorkspace& ws) const;

 private:
  // Steps of query(): the workspace sized and the center queued; a finalized
  // vertex's frame (the center's own, or its parent's transported) and
  // coordinates; the relaxation of its edges.
  void begin_query(int32_t center, DemWorkspace& ws) const;
  void center_frame(int32_t q, DemWorkspace& ws) const;
  void transport_frame(int32_t p, int32_t q, DemWorkspace& ws) const;
  void average_coordinates(int32_t q, DemWorkspace& ws) const;
  void relax(int32_t q, DemWorkspace& ws) const;

  std::vector<double> x_, y_, z_;
  std::vector<double> normal_;       // 3n
  std::vector<int64_t> adj_offsets;  // n + 1
  std::vector<int32_t> adj_;         // neighbors, ascending per vertex
  std::vector<double> len_;          // edge length per adjacency entry
};

}  // namespace locus
