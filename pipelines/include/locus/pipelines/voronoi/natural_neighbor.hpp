// Natural-neighbor (area-stealing) coordinates on a triangle mesh with heat-diffusion
// Voronoi cells (thesis §3.7.2; Sibson's coordinates, cells of §3.4 eq. 3.18).
//
// b_i(q) = (a_i - ã_i) / a_q: a_i is the area of site i's cell, ã_i its area once q
// is inserted as an extra site, a_q the area of q's cell. Areas are those of the
// split-triangle partition (pipelines/voronoi_cell_partition), so coordinates vary
// continuously with q. Inserting q changes the labels only where q's heat is the
// largest, and the split only of triangles with such a vertex: the query solves
// q's heat once (or takes it from the caller, so batches of 8 queries share a solve)
// and re-splits just those triangles; the sites' heat comes from the prepared
// top-K lists (one full Voronoi computation at preparation).
// Properties: b_i >= 0 (tiny negative differences from rounding are clamped and
// reported), sum b_i = 1 (the partition preserves the total area), b_i(p_j) =
// delta_ij (a query at a site's position returns the indicator), locality (sites
// whose cells q does not touch get exactly 0). Linear precision holds in the plane
// up to the discretization of the cells (thesis: not on curved surfaces).
// When q's heat is the largest at no vertex (q much closer to a site than the mesh
// resolves), the result is the indicator of the site whose cell contains q and
// `degenerate` is set.
//
// Sites may also be vertex sets (skinning handles made of several vertices, a
// bone): a set's heat is the solve with a unit source at each of its vertices
// (multi-source heat Voronoi, thesis §3.2), its cell the vertices where that heat
// is the largest. Queries at a vertex of a set return its indicator (degenerate).
//
// Thread safety: a prepared NaturalNeighborField is immutable; queries are re-entrant.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"

namespace locus {

struct NaturalNeighborField {
  const HeatDiffusion* heat = nullptr;  // not owned; must outlive the field
  std::vector<SurfacePoint> sites;
  std::vector<std::array<double, 3>> site_position;
  HeatVoronoi voronoi;                  // full solves: complete top-K lists
  HostVector<double> face_area;        // R^3
  std::vector<int64_t> vf_offsets;      // faces around each vertex (CSR)
  std::vector<int32_t> vf_faces;
  std::vector<double> cell_area;        // a_i
  // Per face, its split among the sites before any insertion (up to 3 parts;
  // part_site -1 = unused): a query re-splits only faces on its cell's border.
  std::vector<int32_t> part_site;       // 3 per face
  std::vector<double> part_area;        // 3 per face
  std::vector<uint8_t> part_fallback;   // per face: split by vertex labels (a heat value was missing)
  // Per vertex, a third of its incident faces' parts summed per site (CSR) and a
  // third of their area: a query adds these over the vertices it takes and
  // re-splits only the faces on its cell's border, so its cost is one pass over
  // its cell's vertices.
  std::vector<int64_t> share_offsets;   // n + 1
  std::vector<int32_t> share_site;
  std::vector<double> share_area;
  std::vector<double> vertex_area;
  // The largest site heat per vertex (top_value's first entry, contiguous: a
  // query's scan for the vertices it takes reads one value per vertex).
  std::vector<double> max_heat;
};

// H: the prepared heat operator of m (isotropic); sites: at least one, valid.
NaturalNeighborField prepare_natural_neighbors(const HeatDiffusion& H, const Mesh& m,
                                                 std::span<const SurfacePoint> sites, const RunContext& ctx);

// The same with vertex-set sites: sets[i] is site i's vertices (non-empty,
// disjoint, valid ids); sites[i] becomes the set's first vertex.
NaturalNeighborField prepare_natural_neighbors(const HeatDiffusion& H, const Mesh& m,
                                                 std::span<const std::vector<int32_t>> sets, const RunContext& ctx);

// Reusable per-thread scratch of the queries (marks sized to the mesh, zero between uses).
struct NaturalScratch {
  std::vector<uint8_t> vertex_mark;  // bit l: lane l (batched queries)
  std::vector<int32_t> lane_faces[8];
  std::vector<int64_t> lane_keys[8];  // (smallest taken corner, face) of each border face
};

struct NaturalCoordinates {
  std::vector<double> weight;  // one per site
  double cell_area = 0;        // a_q
  bool at_site = false;        // q coincides with a site (indicator returned)
  bool degenerate = false;     // q's cell holds no vertex (indicator of the containing cell)
  double clamped = 0;          // sum of negative differences set to zero, relative to a_q
  int64_t fallback_faces = 0;  // re-split triangles lacking a heat value (split by vertex labels)
};

// heat_q[v]: q's heat (M - tL)^{-1} b(q) at every vertex (size n).
NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q, std::span<const double> heat_q);
// The same with caller-owned scratch (batched queries: no allocation once warm).
NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q, std::span<const double> heat_q,
                                                 NaturalScratch& scratch);
// Up to 8 queries q[l] whose heat is heat8[v * 8 + l] (one 8-lane solve, as
// kernels/solve's solve8 leaves it): the same coordinates as one query at a time,
// bit for bit, from one pass over the vertices for all of them (nearby queries
// take mostly the same vertices, whose shares are then read once).
void natural_neighbor_coordinates8(const NaturalNeighborField& F, const Mesh& m, std::span<const SurfacePoint> q,
                                   std::span<const double> heat8, NaturalScratch& scratch,
                                   std::span<NaturalCoordinates> out);
// One-shot: solves q's heat itself.
NaturalCoordinates natural_neighbor_coordinates(const NaturalNeighborField& F, const Mesh& m,
                                                 const SurfacePoint& q);

}  // namespace locus
