// Surface patches grown by breadth-first search on the vertex-edge graph
// (thesis §4.4: "We generate patches ... using BFS on the vertex-edge graph of
// the triangle mesh"), and the patch as a mesh of its own.
//
// Prepare once per mesh (adjacency, vertex-to-face incidence), then grow any
// number of patches with a caller-owned workspace: a query costs O(patch size)
// plus the faces around it, never O(mesh). Patches are reusable by every
// pipeline that works on a region (parameterization, ROI deformation, cells).
//
// Which vertices a patch holds: BFS from the center visits vertices by graph
// distance, neighbors in ascending id order (so the patch is deterministic),
// until `count` vertices are visited. The patch's faces are the mesh faces whose
// corners were all visited, less "ears": a vertex with a single patch face is
// the tip of a spike of the partial last ring (the face has all three corners on
// the boundary); it is dropped with its face, repeatedly, because such spikes are
// not part of a disk-like region and fold over under Neumann data (measured: one
// flipped ear in every 10% patch of a level-4 icosphere). Vertices that end up in
// no patch face are dropped too, so the patch has no isolated vertices and may
// hold slightly fewer than `count` vertices.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/mesh.hpp"

namespace locus {

// Everything patch growing needs of a mesh, computed once. Holds a pointer to
// the mesh: the mesh must outlive it and stay unchanged.
struct PatchGrower {
  const Mesh* mesh = nullptr;
  Adjacency adjacency;
  std::vector<int64_t> vf_offsets;  // nv + 1: faces incident to each vertex (CSR)
  std::vector<int32_t> vf_faces;    //   ascending face ids
};

// Throws BadInput unless `m` is a valid triangle mesh (mesh_topology checks).
PatchGrower prepare_patch_grower(const Mesh& m);

// Per-thread scratch of patch growing; all entries -1 between calls.
struct PatchWorkspace {
  std::vector<int32_t> local;  // nv: local index of a global vertex during a call
};

struct MeshPatch {
  std::vector<int32_t> vertices;  // global ids of the patch vertices, BFS order (center first)
  std::vector<int32_t> faces;     // global ids of the patch faces, ascending
  Mesh mesh;                      // the patch as a mesh: vertex k is vertices[k], face k is faces[k]
  int32_t rings = 0;              // BFS depth reached (the last ring may be partial)
};

// Number of patch vertices for a fraction of the mesh: round(fraction * nv),
// at least 1. Throws BadUsage unless 0 < fraction <= 1.
int32_t patch_vertex_count(int32_t nv, double fraction);

// Grows the BFS patch of `count` vertices around `center` (BadUsage if the
// center is out of range or count < 1; a count above the center's component
// size stops at the whole component).
MeshPatch grow_bfs_patch(const PatchGrower& g, int32_t center, int32_t count, PatchWorkspace& ws);

// The patch spanned by a given vertex set: faces with all corners in the set,
// vertices of those faces in the given order. Same result type, rings = 0.
MeshPatch extract_patch(const PatchGrower& g, std::span<const int32_t> vertices, PatchWorkspace& ws);

}  // namespace locus
