// The restricted-Delaunay dual of a vertex-labelled Voronoi partition of a
// triangle mesh, and the checks that make it a manifold with the input's
// topology (the dual triangulation of thesis §3.7.1, Table 3.7.1).
//
// Cells: the heat Voronoi labels split every triangle along its bisectors
// (eqs. 3.19-3.21), so cell A is a regular neighbourhood of the subcomplex K_A
// spanned by the A-labelled vertices (its vertices, the edges and faces with
// all corners labelled A). A corner of the diagram sits in every face with three
// labels, a piece of the A|B interface in every face holding both labels.
//
// The dual: one vertex per non-empty cell, one triangle (A, B, C) per face whose
// corners carry labels A, B, C in that order (so the triangles inherit the mesh's
// orientation). By the nerve theorem (Edelsbrunner-Shah's closed-ball
// property) the dual is homeomorphic to the mesh when
//   cells:      every cell is a closed disk: K_A connected with Euler
//               characteristic 1;
//   interfaces: every two adjacent cells share one arc (one chain of
//               two-label faces between two endpoints, which are corners or
//               boundary edges), not a closed loop, not two arcs, and not an
//               arc from boundary to boundary;
//   corners:    three cells meet at most once (one face per label triple);
//   boundary:   every cell meets the boundary in at most one arc (one run of
//               its label along the boundary loops) and every boundary loop
//               passes through at least three cells.
// Each violation gives a mesh vertex where a new site splits the offending
// cell or interface (the repair of cvt_remesh.hpp, as ACVD and geogram add
// points); the dual is only assembled when there is none.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

struct DualDefects {
  int64_t split_cells = 0;          // cells in more than one piece
  int64_t non_disk_cells = 0;       // connected cells with Euler characteristic != 1
  int64_t split_interfaces = 0;     // extra arcs of interfaces with more than one
  int64_t loop_interfaces = 0;      // interfaces that are closed loops (no corner)
  int64_t boundary_interfaces = 0;  // arcs from boundary to boundary (a dual edge without triangle)
  int64_t repeated_corners = 0;     // extra corners of label triples met more than once
  int64_t split_boundary_runs = 0;  // extra boundary runs of cells meeting the boundary more than once
  int64_t short_boundary_loops = 0; // boundary loops through fewer than three cells
  int64_t total() const {
    return split_cells + non_disk_cells + split_interfaces + loop_interfaces + boundary_interfaces +
           repeated_corners + split_boundary_runs + short_boundary_loops;
  }
};

// What the dual needs of the mesh, built once per mesh (labels change, this not).
// The edge incidence is the topology's own, or borrowed from the caller's
// derived data (MeshDerived::incidence, ~45 MB at 416k vertices not built twice):
// a borrowed one must outlive the topology and every copy of it.
struct DualTopology {
  EdgeIncidence own;                          // edges, face_count, corner -> edge (when not borrowed)
  const EdgeIncidence* borrowed = nullptr;    // edge_incidence(m) of the caller's, or null
  std::vector<std::vector<int32_t>> loops;    // boundary loops (mesh_topology.hpp order)
  std::vector<uint8_t> sharp_boundary;        // per vertex: boundary corner turning more than 45 degrees,
                                              // not at a seam's end (restricted_dual.cpp)
  const EdgeIncidence& inc() const { return borrowed ? *borrowed : own; }
};
DualTopology dual_topology(const Mesh& m);
// The same on `inc` = edge_incidence(m), borrowed (not copied).
DualTopology dual_topology(const Mesh& m, const EdgeIncidence& inc);

struct RestrictedDual {
  DualDefects defects;
  // One mesh vertex per defect where a new site removes it (deduplicated;
  // vertices already holding a vertex site are skipped).
  std::vector<int32_t> repair_vertices;
  // Assembled only without defects:
  std::vector<std::array<int32_t, 3>> triangles;  // site ids, oriented like the mesh faces
  std::vector<int32_t> corner_face;                // per triangle: the mesh face holding its corner
  std::vector<int32_t> cell_size;                  // per site: vertices of its cell (0 = empty cell)
  // Per site: the boundary vertex its dual vertex moves to (-1: interior cell):
  // a sharp boundary corner of its run when there is one, else the run's vertex
  // nearest the site.
  std::vector<int32_t> boundary_vertex;
};

// label[v] in [0, sites.size()) for every vertex of the triangle mesh m.
RestrictedDual restricted_dual(const Mesh& m, const DualTopology& topo, std::span<const int32_t> label,
                               std::span<const SurfacePoint> sites);

// The dual as a mesh: one vertex per non-empty cell (in site order; the site's
// position, or its boundary vertex), the triangles renumbered. vertex_site[i] is
// the site of remesh vertex i. BadUsage when d has defects.
Mesh dual_mesh(const Mesh& m, const RestrictedDual& d, std::span<const SurfacePoint> sites,
               std::vector<int32_t>& vertex_site);

}  // namespace locus
