// Derived mesh structure (DESIGN.md "Data"): vertex adjacency (CSR), unique
// edges, boundary loops, connected components, Euler characteristic / genus,
// mean edge length, and a validation report. All O(nv + nf log) or better.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

struct Adjacency {              // symmetric vertex graph, no self loops
  std::vector<int64_t> offsets; // nv + 1
  std::vector<int32_t> neighbors;  // sorted ascending per vertex
};

struct Edges {                  // unique undirected edges of the faces, e0 < e1, sorted lexicographically
  std::vector<int32_t> e0, e1;
  std::vector<int32_t> face_count;  // faces incident to each edge (1 boundary, 2 interior, >2 non-manifold)
};

struct MeshReport {
  int32_t n_vertices = 0, n_faces = 0;
  int64_t n_edges = 0;
  std::vector<int64_t> face_degree_histogram;  // index = degree (0..max)
  int32_t components = 0;              // over referenced vertices
  int32_t boundary_loops = 0;
  int64_t euler_characteristic = 0;    // V - E + F (referenced vertices)
  int64_t genus = 0;                   // (2 - chi - b) / 2 when connected and manifold, else -1
  bool manifold = true;
  int64_t non_manifold_edges = 0;      // edges with > 2 faces or inconsistent orientation
  int64_t non_manifold_vertices = 0;   // vertices whose faces form more than one fan
  int64_t degenerate_faces = 0;        // zero area (relative to h^2 * 1e-14)
  int64_t unreferenced_vertices = 0;
  double bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
  double mean_edge_length = 0;
  // First offending elements, for messages (-1 if none).
  int64_t first_non_manifold_edge_v0 = -1, first_non_manifold_edge_v1 = -1;
  int64_t first_degenerate_face = -1, first_unreferenced_vertex = -1;
};

Adjacency vertex_adjacency(const Mesh& m);
Edges unique_edges(const Mesh& m);
// Boundary loops as vertex cycles (edges with exactly one incident face), each in order.
std::vector<std::vector<int32_t>> boundary_loops(const Mesh& m);
// Component id per vertex (unreferenced vertices get their own component id -1), returns count.
int32_t connected_components(const Mesh& m, std::vector<int32_t>& component_of_vertex);
double mean_edge_length(const Mesh& m);
MeshReport analyze_mesh(const Mesh& m);

// What a pipeline needs of its input; check_requirements throws BadInput naming
// the first offending element (face, edge, vertex) and the mesh's source file.
struct MeshRequirements {
  bool triangles = true;
  bool manifold = true;
  bool no_degenerate_faces = true;
  bool no_unreferenced_vertices = true;
  bool connected = false;
  bool closed = false;
};
void check_requirements(const Mesh& m, const MeshRequirements& req);

}  // namespace locus
