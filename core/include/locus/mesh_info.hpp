// What a mesh is and what is wrong with it: sizes, face degrees, topology,
// bounding box, mean edge length, and the defects other commands refuse or
// route to the robust operator (non-manifold edges and vertices, degenerate
// faces, unreferenced vertices). A value type of the core floor because two
// floors fill it: the kernels' one-pass analysis (analyze_mesh, whose report
// extends it with the details messages need) and the engine's report of
// every front end (locus/engine/mesh_info.hpp). Thesis §2.1 (the manifold
// triangle meshes the operators need).
#pragma once
#include <cstdint>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API MeshInfo {
  int32_t n_vertices = 0, n_faces = 0;  // faces as given (polygons stay polygons)
  int64_t n_edges = 0;
  std::vector<int64_t> face_degree_histogram;  // index = vertices per face (0..max)
  int32_t components = 0;                      // over referenced vertices
  int32_t boundary_loops = 0;
  int64_t euler_characteristic = 0;  // V - E + F over referenced vertices
  int64_t genus = -1;                // (2 - chi - b) / 2 for a connected manifold; -1 = undefined
  bool manifold = true;
  int64_t non_manifold_edges = 0;     // edges with more than 2 faces or inconsistent orientation
  int64_t non_manifold_vertices = 0;  // vertices whose faces form more than one fan
  int64_t degenerate_faces = 0;       // zero area (relative to h^2 * 1e-14)
  int64_t unreferenced_vertices = 0;
  double bbox_min[3] = {0, 0, 0}, bbox_max[3] = {0, 0, 0};
  double mean_edge_length = 0;
  // The first offender of each kind, -1 when none.
  int64_t first_non_manifold_edge_v0 = -1, first_non_manifold_edge_v1 = -1;
  int64_t first_non_manifold_vertex = -1, first_degenerate_face = -1, first_unreferenced_vertex = -1;
};

}  // namespace locus
LOCUS_API_END
