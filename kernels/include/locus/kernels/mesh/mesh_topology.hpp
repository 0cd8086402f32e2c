// Derived mesh structure (DESIGN.md "Data"): vertex adjacency (CSR), unique
// edges, boundary loops, connected components, Euler characteristic / genus,
// mean edge length, and a validation report. All O(nv + nf log) or better.
//
// Every function here first checks the mesh arrays themselves (validate_mesh_arrays)
// and throws locus::Error(BadInput) naming the face and vertex when an index is out
// of range, so hostile meshes built through the API never read out of bounds.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/mesh.hpp"
#include "locus/mesh_info.hpp"

namespace locus {

struct Adjacency {              // symmetric vertex graph, no self loops
  HostVector<int64_t> offsets; // nv + 1
  HostVector<int32_t> neighbors;  // sorted ascending per vertex
};

struct Edges {                  // unique undirected edges of the faces, e0 < e1, sorted lexicographically
  HostVector<int32_t> e0, e1;
  HostVector<int32_t> face_count;  // faces incident to each edge (1 boundary, 2 interior, >2 non-manifold)
};

// Edges together with their half-edges. A corner c is an index into
// m.face_vertices; the half-edge of corner c runs from face_vertices[c] to the next
// vertex of the same face. Built by one bucket sort on the smaller endpoint, O(#corners).
struct EdgeIncidence {
  Edges edges;
  HostVector<int32_t> corner_edge;          // per corner: edge id of its half-edge, -1 if both ends coincide
  HostVector<int64_t> edge_corner_offsets;  // ne + 1: CSR of the corners whose half-edge is that edge
  HostVector<int32_t> edge_corners;         //   (ascending corner index, i.e. ascending face)
};

// Frees an incidence's edge-to-corner CSR (edge_corner_offsets, edge_corners:
// 20 MB at 416k vertices) when its holder keeps it for what reads only the
// edges and corner_edge (the Session after its checks). What reads the CSR
// takes it through EdgeCorners, which rebuilds it then.
void drop_edge_corners(EdgeIncidence& inc);

// The corners of each edge of an incidence: its own CSR, borrowed, or when it
// was dropped the same arrays rebuilt from corner_edge (an edge's corners are
// face_count of them; counting them in ascending corner order gives
// edge_incidence's offsets and order), O(#corners).
class EdgeCorners {
 public:
  explicit EdgeCorners(const EdgeIncidence& inc);
  EdgeCorners(const EdgeCorners&) = delete;
  EdgeCorners& operator=(const EdgeCorners&) = delete;
  const int64_t* offsets() const { return offsets_; }  // ne + 1
  const int32_t* corners() const { return corners_; }
  int32_t first(int64_t e) const { return corners_[offsets_[e]]; }  // the edge's corner of lowest index

 private:
  HostVector<int64_t> own_offsets_;
  HostVector<int32_t> own_corners_;
  const int64_t* offsets_ = nullptr;
  const int32_t* corners_ = nullptr;
};

// Throws BadInput (naming the mesh source, face and vertex) unless x/y/z have equal
// length, face_offsets is a non-decreasing CSR starting at 0 and ending at
// face_vertices.size(), every face has >= 3 vertices, every index is in [0, nv), and
// f0/f1/f2 are either empty or hold exactly the faces (all triangles).
void validate_mesh_arrays(const Mesh& m);
// "source" or "mesh" when the mesh was generated, for the prefix of messages.
std::string mesh_name(const Mesh& m);

EdgeIncidence edge_incidence(const Mesh& m);
Adjacency vertex_adjacency(const Mesh& m);
Adjacency vertex_adjacency(const Mesh& m, const Edges& edges);  // from precomputed edges
Edges unique_edges(const Mesh& m);
// Boundary loops as vertex cycles (edges with exactly one incident face), each in order.
// A loop follows the direction of its faces (the surface lies to the left of the walk
// for counter-clockwise faces). Loops are found in order of their lowest-numbered
// boundary edge and start at the tail of that edge's half-edge. At non-manifold
// boundary vertices (more than two boundary edges) the walk prefers the first unused
// boundary edge leaving the vertex in face direction.
// With the incidence given, a triangle mesh's corners are read through
// f0/f1/f2: its face_vertices may be lent out meanwhile (the cvt command's
// repair reads the loops while it holds them).
std::vector<std::vector<int32_t>> boundary_loops(const Mesh& m);
std::vector<std::vector<int32_t>> boundary_loops(const Mesh& m, const EdgeIncidence& inc);
// Component id per vertex (unreferenced vertices get their own component id -1), returns count.
// Components are numbered in order of their smallest vertex.
int32_t connected_components(const Mesh& m, std::vector<int32_t>& component_of_vertex);
double mean_edge_length(const Mesh& m);
double mean_edge_length(const Mesh& m, const Edges& edges);

// MeshInfo (the front ends' report) and the details messages need.
struct MeshReport : MeshInfo {
  int64_t boundary_edges = 0;
  int64_t first_non_manifold_edge_faces = -1;   // face count of that edge (2 = inconsistent orientation)
  int64_t first_non_manifold_edge_face_a = -1;  // two of the faces on that edge
  int64_t first_non_manifold_edge_face_b = -1;
  int64_t first_non_manifold_vertex_fans = 0;
  int64_t first_non_triangle_face = -1;
  int64_t first_boundary_vertex = -1;           // a vertex of the first boundary loop
  int64_t non_finite_vertices = 0;              // vertices with a NaN or infinite coordinate
  int64_t first_non_finite_vertex = -1;
};

// Degenerate-face threshold: a face is degenerate when its area is not above
// kDegenerateAreaRelative * h^2 (h = mean edge length), or not finite.
inline constexpr double kDegenerateAreaRelative = 1e-14;

// 2^-k with h * 2^-k in [1, 2): area and angle computations multiply edge
// vectors by it so that cross products neither underflow (a mesh scaled by
// 1e-149) nor overflow (1e149; coordinate_range.hpp bounds the sizes). A power
// of two scales exactly, so results on ordinary meshes equal the unscaled
// formulas' (up to where the compiler fuses multiply-adds: the geodesic
// snapshot moved in the 16th digit when this was introduced).
inline double power_of_two_scale(double h) {
  return h > 0 && h <= std::numeric_limits<double>::max() ? std::ldexp(1.0, -std::ilogb(h)) : 1.0;
}

MeshReport analyze_mesh(const Mesh& m);
// The same with the mesh's edge incidence given (edge_incidence(m)).
MeshReport analyze_mesh(const Mesh& m, const EdgeIncidence& inc);

// What a pipeline needs of its input; check_requirements throws BadInput naming
// the first offending element (face, edge, vertex) and the mesh's source file.
// Checks run in this order: finite coordinates, a size whose areas double
// precision holds (with finite_coordinates; coordinate_range.hpp), triangles,
// unreferenced vertices, degenerate faces, manifold edges, manifold vertices,
// connected, closed.
struct MeshRequirements {
  bool triangles = true;
  bool manifold = true;
  bool no_degenerate_faces = true;
  bool no_unreferenced_vertices = true;
  bool connected = false;
  bool closed = false;
  bool finite_coordinates = true;  // (added last so existing designated initializers still compile)
};
void check_requirements(const Mesh& m, const MeshRequirements& req);
void check_requirements(const Mesh& m, const MeshRequirements& req, const MeshReport& report);

}  // namespace locus
