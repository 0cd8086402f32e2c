// The patch grower (kernels/include/locus/kernels/mesh/patch_grower.hpp; thesis §4.4).
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/core/host_allocator.hpp"

#include "locus/kernels/mesh/index_min_heap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

// The shared index heap (locus/kernels/mesh/index_min_heap.hpp) on ws.dist, positions in ws.level.
inline void sift_up(GrowWorkspace& ws, int32_t pos) { index_heap_sift_up(ws.heap, ws.dist.data(), ws.level.data(), pos); }
inline int32_t pop_min(GrowWorkspace& ws) { return index_heap_pop_min(ws.heap, ws.dist.data(), ws.level.data()); }

void prepare_workspace(GrowWorkspace& ws, int32_t n, bool geodesic) {
  if (ws.state.size() != static_cast<size_t>(n)) {
    ws.dist.clear();
    ws.level.assign(static_cast<size_t>(n), -1);
    ws.state.assign(static_cast<size_t>(n), 0);
  }
  if (geodesic && ws.dist.size() != static_cast<size_t>(n))
    ws.dist.assign(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  ws.heap.clear();
  ws.touched.clear();
}

// BFS: `out` doubles as the queue. ws.level holds the depth of a seen vertex.
int32_t grow_rings(const Adjacency& adj, std::span<const GrowSeed> seeds, int32_t count, GrowWorkspace& ws,
                   HostVector<int32_t>& out) {
  uint8_t* state = ws.state.data();
  int32_t* depth = ws.level.data();
  for (const GrowSeed& s : seeds) {
    if (static_cast<int32_t>(out.size()) == count) break;
    if (state[s.vertex]) continue;
    state[s.vertex] = 2;
    depth[s.vertex] = 0;
    out.push_back(s.vertex);
  }
  int32_t rings = 0;
  for (size_t head = 0; head < out.size() && static_cast<int32_t>(out.size()) < count; ++head) {
    const int32_t v = out[head];
    for (int64_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
      const int32_t w = adj.neighbors[k];
      if (state[w]) continue;
      state[w] = 2;
      depth[w] = depth[v] + 1;
      rings = std::max(rings, depth[w]);
      out.push_back(w);
      if (static_cast<int32_t>(out.size()) == count) break;
    }
  }
  for (int32_t v : out) {
    state[v] = 0;
    depth[v] = -1;
  }
  return rings;
}

// What a plain grow records besides the order: nothing.
struct NoLabels {
  void seed(int32_t, size_t) {}
  void edge(int32_t, int32_t) {}
};

// Which seed's path reached each vertex (label_nearest_seeds): set whenever the
// vertex's tentative distance is set or strictly lowered.
struct SeedLabels {
  std::span<const int32_t> seed_label;
  std::span<int32_t> label;
  void seed(int32_t v, size_t k) { label[v] = seed_label[k]; }
  void edge(int32_t r, int32_t q) { label[r] = label[q]; }
};

// Dijkstra with the DEM's heap; ws.touched lists every vertex whose state was set.
// `rec` hears of every distance set (rec.seed: from seed k; rec.edge: from vertex q).
// `len(a, q, r)`: the length of adjacency entry a (from vertex q to its neighbor r).
template <class Length, class Recorder>
void grow_geodesic(const Adjacency& adj, Length&& len, std::span<const GrowSeed> seeds, const GrowOptions& opt,
                   GrowWorkspace& ws, HostVector<int32_t>& out, Recorder&& rec) {
  double* dist = ws.dist.data();
  uint8_t* state = ws.state.data();
  const bool prune = opt.radius_rule == RadiusRule::PruneBeyond;
  const double radius = opt.max_radius;
  for (size_t k = 0; k < seeds.size(); ++k) {
    const GrowSeed& s = seeds[k];
    if (state[s.vertex] == 0) {
      state[s.vertex] = 1;
      ws.touched.push_back(s.vertex);
      dist[s.vertex] = s.distance;
      rec.seed(s.vertex, k);
      ws.heap.push_back(s.vertex);
      sift_up(ws, static_cast<int32_t>(ws.heap.size()) - 1);
    } else if (s.distance < dist[s.vertex]) {
      dist[s.vertex] = s.distance;
      rec.seed(s.vertex, k);
      sift_up(ws, ws.level[s.vertex]);
    }
  }
  while (!ws.heap.empty() && static_cast<int32_t>(out.size()) < opt.max_vertices) {
    if (!prune && dist[ws.heap[0]] > radius) break;
    const int32_t q = pop_min(ws);
    state[q] = 2;
    out.push_back(q);
    const double dq = dist[q];
    for (int64_t a = adj.offsets[q]; a < adj.offsets[q + 1]; ++a) {
      const int32_t r = adj.neighbors[a];
      if (state[r] == 2) continue;
      const double nd = dq + len(a, q, r);
      if (prune && !(nd <= radius)) continue;
      if (state[r] == 0) {
        state[r] = 1;
        ws.touched.push_back(r);
        dist[r] = nd;
        rec.edge(r, q);
        ws.heap.push_back(r);
        sift_up(ws, static_cast<int32_t>(ws.heap.size()) - 1);
      } else if (nd < dist[r]) {
        dist[r] = nd;
        rec.edge(r, q);
        sift_up(ws, ws.level[r]);
      }
    }
  }
  for (int32_t t : ws.touched) {
    dist[t] = std::numeric_limits<double>::infinity();
    state[t] = 0;
    ws.level[t] = -1;
  }
  ws.heap.clear();
  ws.touched.clear();
}

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
  HostVector<uint8_t> dropped(p.faces.size(), 0);
  HostVector<int32_t> tips;
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

void check_seeds(std::span<const GrowSeed> seeds, int32_t nv) {
  for (const GrowSeed& s : seeds)
    if (s.vertex < 0 || s.vertex >= nv)
      fail(ErrorCode::BadUsage, "patch center is vertex " + std::to_string(s.vertex) + ", outside 0.." +
                                    std::to_string(nv - 1));
}

// Edge lengths from the positions as a grow reaches them: adjacency_edge_lengths'
// expression (neighbor minus vertex, x, y, z), so the same bits.
struct PositionLength {
  const Mesh& m;
  double operator()(int64_t, int32_t i, int32_t j) const {
    return adjacency_edge_length(m, i, j);
  }
};

void check_edge_lengths(const Adjacency& adj, std::span<const double> edge_length) {
  if (edge_length.size() != adj.neighbors.size())
    fail(ErrorCode::BadUsage, "patch grower: geodesic mode needs one edge length per adjacency entry (" +
                                  std::to_string(edge_length.size()) + " for " +
                                  std::to_string(adj.neighbors.size()) + ")");
}

}  // namespace

int32_t grow_vertices(const Adjacency& adj, std::span<const double> edge_length, std::span<const GrowSeed> seeds,
                      const GrowOptions& opt, GrowWorkspace& ws, HostVector<int32_t>& out) {
  const int32_t nv = static_cast<int32_t>(adj.offsets.size()) - 1;
  out.clear();
  if (seeds.empty()) fail(ErrorCode::BadUsage, "patch grower: no seed vertex");
  check_seeds(seeds, nv);
  if (opt.max_vertices < 1)
    fail(ErrorCode::BadUsage, "patch vertex count must be >= 1, got " + std::to_string(opt.max_vertices));
  prepare_workspace(ws, nv, opt.mode == GrowMode::Geodesic);
  if (opt.mode == GrowMode::Rings) {
    out.reserve(std::min<size_t>(static_cast<size_t>(opt.max_vertices), static_cast<size_t>(nv)));
    return grow_rings(adj, seeds, opt.max_vertices, ws, out);
  }
  check_edge_lengths(adj, edge_length);
  if (!(opt.max_radius >= 0)) fail(ErrorCode::BadUsage, "patch grower: the radius must be >= 0");
  grow_geodesic(adj, [&](int64_t a, int32_t, int32_t) { return edge_length[a]; }, seeds, opt, ws, out, NoLabels{});
  return 0;
}

void grow_geodesic_vertices(const Adjacency& adj, const Mesh& m, std::span<const GrowSeed> seeds,
                            const GrowOptions& opt, GrowWorkspace& ws, HostVector<int32_t>& out) {
  const int32_t nv = static_cast<int32_t>(adj.offsets.size()) - 1;
  out.clear();
  if (seeds.empty()) fail(ErrorCode::BadUsage, "patch grower: no seed vertex");
  if (nv != m.num_vertices()) fail(ErrorCode::BadUsage, "patch grower: the adjacency belongs to another mesh");
  check_seeds(seeds, nv);
  if (opt.max_vertices < 1)
    fail(ErrorCode::BadUsage, "patch vertex count must be >= 1, got " + std::to_string(opt.max_vertices));
  if (!(opt.max_radius >= 0)) fail(ErrorCode::BadUsage, "patch grower: the radius must be >= 0");
  prepare_workspace(ws, nv, true);
  grow_geodesic(adj, PositionLength{m}, seeds, opt, ws, out, NoLabels{});
}

namespace {

template <class Length>
void label_nearest(const Adjacency& adj, Length&& length, std::span<const GrowSeed> seeds,
                   std::span<const int32_t> seed_label, GrowWorkspace& ws, std::span<int32_t> label) {
  std::fill(label.begin(), label.end(), -1);
  prepare_workspace(ws, static_cast<int32_t>(adj.offsets.size()) - 1, true);
  HostVector<int32_t> settled;
  grow_geodesic(adj, length, seeds, GrowOptions{GrowMode::Geodesic}, ws, settled, SeedLabels{seed_label, label});
}

void check_labels(const Adjacency& adj, std::span<const GrowSeed> seeds, std::span<const int32_t> seed_label,
                  std::span<int32_t> label) {
  const int32_t nv = static_cast<int32_t>(adj.offsets.size()) - 1;
  if (label.size() != static_cast<size_t>(nv))
    fail(ErrorCode::BadUsage, "seed labels: one label per vertex expected");
  if (seed_label.size() != seeds.size()) fail(ErrorCode::BadUsage, "seed labels: one label per seed expected");
  check_seeds(seeds, nv);
}

}  // namespace

void label_nearest_seeds(const Adjacency& adj, std::span<const double> edge_length, std::span<const GrowSeed> seeds,
                         std::span<const int32_t> seed_label, GrowWorkspace& ws, std::span<int32_t> label) {
  check_labels(adj, seeds, seed_label, label);
  check_edge_lengths(adj, edge_length);
  label_nearest(adj, [&](int64_t a, int32_t, int32_t) { return edge_length[a]; }, seeds, seed_label, ws, label);
}

void label_nearest_seeds_by_positions(const Adjacency& adj, const Mesh& m, std::span<const GrowSeed> seeds,
                                      std::span<const int32_t> seed_label, GrowWorkspace& ws, std::span<int32_t> label) {
  if (adj.offsets.size() != static_cast<size_t>(m.num_vertices()) + 1)
    fail(ErrorCode::BadUsage, "seed labels: the adjacency belongs to another mesh");
  check_labels(adj, seeds, seed_label, label);
  label_nearest(adj, PositionLength{m}, seeds, seed_label, ws, label);
}

std::vector<int32_t> grow_ring_vertices(const Adjacency& adj, int32_t seed, int32_t count) {
  GrowWorkspace ws;
  HostVector<int32_t> out;
  const GrowSeed s{seed, 0.0};
  grow_vertices(adj, {}, {&s, 1}, ring_patch(std::max(count, 1)), ws, out);
  return std::vector<int32_t>(out);
}

HostVector<double> adjacency_edge_lengths(const Mesh& m, const Adjacency& adj) {
  const int32_t nv = m.num_vertices();
  if (adj.offsets.size() != static_cast<size_t>(nv) + 1)
    fail(ErrorCode::BadUsage, "edge lengths: the adjacency belongs to another mesh");
  // The DEM's (and the old CVT balls') edge lengths, bit for bit.
  HostVector<double> len(adj.neighbors.size());
  for (int32_t i = 0; i < nv; ++i) {
    cancel_point(i);
    for (int64_t q = adj.offsets[i]; q < adj.offsets[i + 1]; ++q)
      len[q] = adjacency_edge_length(m, i, adj.neighbors[q]);
  }
  return len;
}

PatchGrower prepare_patch_grower(const Mesh& m) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": patches need a triangle mesh");
  return prepare_patch_grower(m, vertex_adjacency(m));
}

PatchGrower prepare_patch_grower(const Mesh& m, const Adjacency& adjacency) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": patches need a triangle mesh");
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  if (adjacency.offsets.size() != static_cast<size_t>(nv) + 1)
    fail(ErrorCode::BadUsage, "patch grower: the adjacency belongs to another mesh");
  PatchGrower g;
  g.mesh = &m;
  g.adjacency = adjacency;
  g.edge_length = adjacency_edge_lengths(m, g.adjacency);
  g.vf_offsets.assign(static_cast<size_t>(nv) + 1, 0);
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) ++g.vf_offsets[v + 1];
  for (int32_t v = 0; v < nv; ++v) g.vf_offsets[v + 1] += g.vf_offsets[v];
  g.vf_faces.resize(static_cast<size_t>(g.vf_offsets[nv]));
  HostVector<int64_t> next(g.vf_offsets.begin(), g.vf_offsets.end() - 1);
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

int32_t grow_patch_vertices(const PatchGrower& g, int32_t center, const GrowOptions& opt, PatchWorkspace& ws,
                            HostVector<int32_t>& out) {
  if (!g.mesh) fail(ErrorCode::BadUsage, "patch: the grower was not prepared (prepare_patch_grower)");
  const GrowSeed s{center, 0.0};
  return grow_vertices(g.adjacency, g.edge_length, {&s, 1}, opt, ws.grow, out);
}

MeshPatch grow_patch(const PatchGrower& g, int32_t center, const GrowOptions& opt, PatchWorkspace& ws) {
  check_workspace(g, ws);
  HostVector<int32_t> selected;
  const int32_t rings = grow_patch_vertices(g, center, opt, ws, selected);
  for (int32_t v : selected) ws.local[v] = 0;
  MeshPatch p = assemble(g, std::vector<int32_t>(selected), ws);
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
