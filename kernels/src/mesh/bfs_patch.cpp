// BFS surface patches (kernels/include/locus/kernels/mesh/bfs_patch.hpp; thesis §4.4).
#include "locus/kernels/mesh/bfs_patch.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

void check_workspace(const PatchGrower& g, PatchWorkspace& ws) {
  if (!g.mesh) fail(ErrorCode::BadUsage, "patch: the grower was not prepared (prepare_patch_grower)");
  const size_t nv = static_cast<size_t>(g.mesh->num_vertices());
  if (ws.local.size() != nv) ws.local.assign(nv, -1);
}

// Builds the patch from `visited` (global ids, in order), whose entries are
// marked in ws.local (any value >= 0). Leaves ws.local all -1.
MeshPatch assemble(const PatchGrower& g, std::vector<int32_t> visited, PatchWorkspace& ws) {
  const Mesh& m = *g.mesh;
  MeshPatch p;
  // Faces with every corner visited, each taken once: from its first corner.
  for (int32_t v : visited)
    for (int64_t k = g.vf_offsets[v]; k < g.vf_offsets[v + 1]; ++k) {
      const int32_t f = g.vf_faces[k];
      if (m.f0[f] != v || ws.local[m.f1[f]] < 0 || ws.local[m.f2[f]] < 0) continue;
      p.faces.push_back(f);
    }
  std::sort(p.faces.begin(), p.faces.end());
  p.faces.erase(std::unique(p.faces.begin(), p.faces.end()), p.faces.end());

  // Trim ears: a visited vertex with a single patch face is the tip of a spike of
  // the partial last ring (all three corners on the boundary). Such spikes carry
  // concentrated Neumann data and fold over in a parameterization, and they are
  // not part of a disk-like region; drop them until none is left. ws.local holds
  // the number of patch faces per visited vertex meanwhile.
  for (int32_t v : visited) ws.local[v] = 0;
  for (int32_t f : p.faces) ++ws.local[m.f0[f]], ++ws.local[m.f1[f]], ++ws.local[m.f2[f]];
  std::vector<uint8_t> dropped(p.faces.size(), 0);
  std::vector<int32_t> tips;
  for (int32_t v : visited)
    if (ws.local[v] == 1) tips.push_back(v);
  while (!tips.empty()) {
    const int32_t v = tips.back();
    tips.pop_back();
    if (ws.local[v] != 1) continue;
    for (int64_t k = g.vf_offsets[v]; k < g.vf_offsets[v + 1]; ++k) {
      const int32_t f = g.vf_faces[k];
      const auto it = std::lower_bound(p.faces.begin(), p.faces.end(), f);
      if (it == p.faces.end() || *it != f || dropped[it - p.faces.begin()]) continue;
      dropped[it - p.faces.begin()] = 1;
      for (int32_t w : {m.f0[f], m.f1[f], m.f2[f]})
        if (--ws.local[w] == 1) tips.push_back(w);
    }
  }
  size_t kept = 0;
  for (size_t k = 0; k < p.faces.size(); ++k)
    if (!dropped[k]) p.faces[kept++] = p.faces[k];
  p.faces.resize(kept);
  for (int32_t v : visited) ws.local[v] = -1;

  // Keep the visited vertices that are corners of kept faces, in visit order.
  for (int32_t f : p.faces) ws.local[m.f0[f]] = ws.local[m.f1[f]] = ws.local[m.f2[f]] = 0;
  for (int32_t v : visited)
    if (ws.local[v] == 0) {
      ws.local[v] = static_cast<int32_t>(p.vertices.size());
      p.vertices.push_back(v);
    }
  const size_t np = p.vertices.size();
  p.mesh.x.resize(np);
  p.mesh.y.resize(np);
  p.mesh.z.resize(np);
  for (size_t k = 0; k < np; ++k) {
    p.mesh.x[k] = m.x[p.vertices[k]];
    p.mesh.y[k] = m.y[p.vertices[k]];
    p.mesh.z[k] = m.z[p.vertices[k]];
  }
  p.mesh.face_offsets.reserve(p.faces.size() + 1);
  p.mesh.face_vertices.reserve(3 * p.faces.size());
  for (int32_t f : p.faces) p.mesh.add_triangle(ws.local[m.f0[f]], ws.local[m.f1[f]], ws.local[m.f2[f]]);
  p.mesh.source = m.source.empty() ? std::string("patch") : m.source + " (patch)";
  for (int32_t v : p.vertices) ws.local[v] = -1;
  return p;
}

}  // namespace

PatchGrower prepare_patch_grower(const Mesh& m) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": patches need a triangle mesh");
  PatchGrower g;
  g.mesh = &m;
  g.adjacency = vertex_adjacency(m);
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  g.vf_offsets.assign(static_cast<size_t>(nv) + 1, 0);
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) ++g.vf_offsets[v + 1];
  for (int32_t v = 0; v < nv; ++v) g.vf_offsets[v + 1] += g.vf_offsets[v];
  g.vf_faces.resize(static_cast<size_t>(g.vf_offsets[nv]));
  std::vector<int64_t> next(g.vf_offsets.begin(), g.vf_offsets.end() - 1);
  for (int32_t f = 0; f < nf; ++f)  // ascending f, so each list is ascending
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) g.vf_faces[next[v]++] = f;
  return g;
}

int32_t patch_vertex_count(int32_t nv, double fraction) {
  if (!(fraction > 0.0 && fraction <= 1.0))
    fail(ErrorCode::BadUsage, "patch fraction must be in (0, 1], got " + std::to_string(fraction));
  const double c = std::round(fraction * static_cast<double>(nv));
  return static_cast<int32_t>(std::max(1.0, std::min(c, static_cast<double>(nv))));
}

MeshPatch grow_bfs_patch(const PatchGrower& g, int32_t center, int32_t count, PatchWorkspace& ws) {
  check_workspace(g, ws);
  const int32_t nv = g.mesh->num_vertices();
  if (center < 0 || center >= nv)
    fail(ErrorCode::BadUsage, "patch center is vertex " + std::to_string(center) + ", outside 0.." + std::to_string(nv - 1));
  if (count < 1) fail(ErrorCode::BadUsage, "patch vertex count must be >= 1, got " + std::to_string(count));
  // The visit order doubles as the BFS queue; ws.local holds the BFS depth while growing.
  std::vector<int32_t> visited;
  visited.reserve(static_cast<size_t>(count));
  visited.push_back(center);
  ws.local[center] = 0;
  int32_t rings = 0;
  for (size_t head = 0; head < visited.size() && static_cast<int32_t>(visited.size()) < count; ++head) {
    const int32_t v = visited[head];
    for (int64_t k = g.adjacency.offsets[v]; k < g.adjacency.offsets[v + 1]; ++k) {
      const int32_t w = g.adjacency.neighbors[k];
      if (ws.local[w] >= 0) continue;
      ws.local[w] = ws.local[v] + 1;
      rings = std::max(rings, ws.local[w]);
      visited.push_back(w);
      if (static_cast<int32_t>(visited.size()) == count) break;
    }
  }
  MeshPatch p = assemble(g, std::move(visited), ws);
  p.rings = rings;
  return p;
}

MeshPatch extract_patch(const PatchGrower& g, std::span<const int32_t> vertices, PatchWorkspace& ws) {
  check_workspace(g, ws);
  const int32_t nv = g.mesh->num_vertices();
  std::vector<int32_t> visited;
  visited.reserve(vertices.size());
  for (size_t k = 0; k < vertices.size(); ++k) {
    const int32_t v = vertices[k];
    if (v < 0 || v >= nv) {
      for (int32_t u : visited) ws.local[u] = -1;
      fail(ErrorCode::BadUsage, "patch vertex " + std::to_string(k) + " is " + std::to_string(v) + ", outside 0.." +
                                    std::to_string(nv - 1));
    }
    if (ws.local[v] >= 0) continue;  // repeated id: keep the first
    ws.local[v] = 0;
    visited.push_back(v);
  }
  return assemble(g, std::move(visited), ws);
}

}  // namespace locus
