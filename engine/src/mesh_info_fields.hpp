// The numeric fields of the mesh report (engine/include/locus/engine/mesh_info.hpp)
// that the kernels' analysis (kernels/.../mesh/mesh_topology.hpp) and the C
// report (locus_info_report) name alike: one list for both copies
// (engine/src/mesh_info.cpp, c_api_info_command.cpp; field_copy.hpp).
#pragma once

#define LOCUS_MESH_INFO_NUMBERS                                                                                   \
  n_vertices, n_faces, n_edges, components, boundary_loops, euler_characteristic, genus, manifold,               \
      non_manifold_edges, non_manifold_vertices, degenerate_faces, unreferenced_vertices, mean_edge_length,      \
      first_non_manifold_edge_v0, first_non_manifold_edge_v1, first_non_manifold_vertex, first_degenerate_face, \
      first_unreferenced_vertex
