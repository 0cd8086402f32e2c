// Fractional partition of a triangle mesh among heat-Voronoi cells (thesis §3.4,
// eqs. 3.19-3.21, used for the cell sources of §3.2 eqs. 3.9-3.11 and §3.5).
//
// Vertex labels (eq. 3.18) put every triangle wholly into one cell, so a cell is a
// union of vertex stars and moves in jumps of a vertex: Lloyd's method then stops at
// a discrete fixed point far from the CVT (measurements in docs/cvt.md). Here a
// triangle whose corners carry two or three labels is split where the linearly
// interpolated heat values of those labels are equal (the same interpolants as the
// diagram curves, eqs. 3.19-3.21): the part of label l is the convex polygon
// {x : u_l(x) >= u_m(x) for the other labels m of the triangle}, clipped in
// barycentric coordinates. Each part contributes the exact integrals of the hat
// functions over it, int phi_i = area(part) * b_i(centroid of part), so a cell's
// load vector is b_i = int_C phi_i dA (the source of eq. 3.7 with h = chi_C) and
// its area is sum_i b_i. Whole triangles give area/3 per corner (the lumped mass).
//
// Heat values come from the top-K lists of HeatVoronoi; a split triangle for which
// a needed value is missing there (rare: localized solves or more than K labels
// nearby) is split by its vertex labels instead, and counted.
// Ties (equal interpolants over a whole triangle) go to the smaller label.
//
// Deterministic (fixed face chunks concatenated in order, per-cell sorted output,
// each cell's sums in a fixed order), parallel with oneTBB in the caller's arena.
// Thread safety: re-entrant; `face_area` is read only.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/kernels/mesh/lifted_metric.hpp"  // face_areas, face_areas_from_positions
#include "locus/pipelines/voronoi/heat_voronoi.hpp"

namespace locus {

struct CellPartition {
  HostVector<int64_t> offsets;  // cells + 1 (CSR)
  HostVector<int32_t> vertex;   // per cell: vertices with a nonzero load, ascending
  HostVector<double> load;      // int_C phi_vertex dA, in the metric of face_area
  HostVector<double> area;      // per cell
  int64_t split_faces = 0;       // triangles shared by two or three cells
  int64_t fallback_faces = 0;    // of those, split by vertex labels (a heat value was missing)
};

// face_area[f]: area of triangle f in the operator's metric (R^3, or the lifted R^6).
// V.label[v] in [0, cells). Throws BadUsage on size mismatches or bad labels.
CellPartition partition_cells(const Mesh& m, std::span<const double> face_area, const HeatVoronoi& V,
                              int32_t cells);

// The triangles around each vertex, for cell-by-cell work: per vertex (CSR) its
// incident faces, ascending; a face's vertices (in face order) come from the
// mesh's triangle arrays f0/f1/f2 (not face_vertices, which the cvt command
// lends out during Lloyd) and its area (in the operator's metric) from `area`.
// 20 MB at 416k vertices, against 50 MB for a copy of the three vertices and
// the area per (vertex, face) entry.
struct VertexStars {
  std::span<const int64_t> offsets;  // n + 1
  std::span<const int32_t> faces;    // incident triangles of each vertex, ascending face id
  HostVector<double> area;           // per face
  std::span<const int32_t> f0, f1, f2;  // the mesh's triangles: must outlive the stars
  HostVector<int64_t> own_offsets;   // offsets and faces when built here (else borrowed)
  HostVector<int32_t> own_faces;
};
VertexStars vertex_stars(const Mesh& m, std::span<const double> face_area);
// The same, taking the areas instead of copying them.
VertexStars vertex_stars(const Mesh& m, HostVector<double>&& face_area);
// The same on face lists the caller built already (CentroidGeometry's vf_offsets
// and vf_faces are these lists): borrowed, so they must outlive the stars.
VertexStars vertex_stars(const Mesh& m, std::span<const int64_t> vf_offsets, std::span<const int32_t> vf_faces,
                         HostVector<double>&& face_area);

// The same loads for one cell c only, for callers that work cell by cell (Lloyd's
// centroid step computes each cell's source inside its own solve task, so no pass
// over the whole mesh is needed): every triangle incident to a vertex of `cell`
// (the vertices labelled c, ascending) is visited once, from its first corner
// labelled c, and its part of cell c is split off as above. The loads are added to
// acc[i] (all zero on entry at untouched vertices; loads are positive), and each
// vertex that becomes nonzero is appended to `touched` (vertices of the cell and
// across its boundary). Same values as partition_cells up to the order of the
// additions. Returns the cell's area; `fallback` counts the split triangles split by
// vertex labels whose smallest label is c (so that summing over all cells counts
// each triangle once).
double accumulate_cell_load(const VertexStars& stars, const HeatVoronoi& V, int32_t c, std::span<const int32_t> cell,
                            std::span<double> acc, std::vector<int32_t>& touched, int64_t& fallback);
// The same loads without a dense n-vector: the k-th vertex appended to `touched`
// gets its load in load[k] (appended alike; the same sums in the same order as
// acc[v] above). slot: n entries, all -1 on entry and again on return (where
// the call's vertices are in `load` meanwhile).
double accumulate_cell_load(const VertexStars& stars, const HeatVoronoi& V, int32_t c, std::span<const int32_t> cell,
                            std::span<int32_t> slot, std::vector<double>& load, std::vector<int32_t>& touched,
                            int64_t& fallback);

// The cells' areas alone (partition_cells' `area`, bit for bit when the stars hold
// the same face areas) without the mesh-wide list of loads: cell by cell in
// parallel from the stars, each cell's loads summed in partition_cells' order.
// cell_offsets (cells + 1) and cell_vertices: the vertices of each cell (CSR, as
// CellGraph's offsets and verts). Deterministic for any thread count.
HostVector<double> cell_areas(const VertexStars& stars, const HeatVoronoi& V, std::span<const int64_t> cell_offsets,
                              std::span<const int32_t> cell_vertices);

// One triangle: nl (1..3) distinct labels lab[a] with heat u[a][k] at corner k.
// fraction[a]: the share of the triangle's area of label a's part (the shares sum
// to 1); centroid[a]: barycentric coordinates of that part's centroid.
void split_triangle(int nl, const int32_t* lab, const double (*u)[3], double* fraction, double (*centroid)[3]);

}  // namespace locus
