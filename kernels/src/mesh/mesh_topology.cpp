// Combinatorial structure of a polygon mesh (DESIGN.md "Data": vertex adjacency
// CSR, unique edges e0 < e1, boundary loops, components). Not from the thesis:
// these are the derived arrays every chapter's operators are assembled from.
//
// Unique edges come from one bucket (counting) sort of the half-edges on their
// smaller endpoint followed by a tiny sort inside each bucket (a vertex has ~6
// neighbors), so the cost is O(#corners) in practice and O(#corners log d) at
// worst, with no hashing and no std::map. The same pass records, for every
// corner, the edge its half-edge lies on, which is what the operator assembly
// (mesh_operators.cpp) and the manifold checks (mesh_topology_report.cpp) need.
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/core/host_allocator.hpp"
#include "mesh_topology_union_find.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

std::string mesh_name(const Mesh& m) { return m.source.empty() ? std::string("mesh") : m.source; }

void validate_mesh_arrays(const Mesh& m) {
  const std::string name = mesh_name(m);
  if (m.y.size() != m.x.size() || m.z.size() != m.x.size())
    fail(ErrorCode::BadInput, name + ": coordinate arrays differ in length (x " + std::to_string(m.x.size()) + ", y " +
                                  std::to_string(m.y.size()) + ", z " + std::to_string(m.z.size()) + ")");
  if (m.x.size() > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    fail(ErrorCode::BadInput, name + ": more than 2^31-1 vertices");
  if (m.face_offsets.empty() || m.face_offsets[0] != 0)
    fail(ErrorCode::BadInput, name + ": face_offsets must start with 0");
  if (m.face_offsets.size() - 1 > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    fail(ErrorCode::BadInput, name + ": more than 2^31-1 faces");
  if (static_cast<size_t>(m.face_offsets.back()) != m.face_vertices.size() || m.face_offsets.back() < 0)
    fail(ErrorCode::BadInput, name + ": face_offsets ends at " + std::to_string(m.face_offsets.back()) +
                                  " but there are " + std::to_string(m.face_vertices.size()) + " face vertices");
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t b = m.face_offsets[f], e = m.face_offsets[f + 1];
    if (e < b || b < 0 || static_cast<size_t>(e) > m.face_vertices.size())
      fail(ErrorCode::BadInput, name + ": face_offsets decreases at face " + std::to_string(f));
    if (e - b < 3)
      fail(ErrorCode::BadInput, name + ": face " + std::to_string(f) + " has " + std::to_string(e - b) +
                                    " vertices; a face needs at least 3");
    for (int32_t c = b; c < e; ++c) {
      const int32_t v = m.face_vertices[c];
      if (v < 0 || v >= nv)
        fail(ErrorCode::BadInput, name + ": face " + std::to_string(f) + " references vertex " + std::to_string(v) +
                                      " but the mesh has " + std::to_string(nv) + " vertices");
    }
  }
  if (!m.f0.empty() || !m.f1.empty() || !m.f2.empty()) {
    const size_t n = static_cast<size_t>(nf);
    if (m.f0.size() != n || m.f1.size() != n || m.f2.size() != n)
      fail(ErrorCode::BadInput, name + ": triangle arrays f0/f1/f2 do not match the " + std::to_string(nf) + " faces");
    for (int32_t f = 0; f < nf; ++f) {
      const int32_t* v = m.face_vertices.data() + m.face_offsets[f];
      if (m.face_offsets[f + 1] - m.face_offsets[f] != 3 || m.f0[f] != v[0] || m.f1[f] != v[1] || m.f2[f] != v[2])
        fail(ErrorCode::BadInput, name + ": triangle arrays f0/f1/f2 disagree with face " + std::to_string(f));
    }
  }
}

namespace {

// Sorts a short run of keys; buckets are vertex neighborhoods, mostly < 16 long.
void sort_bucket(uint64_t* b, uint64_t* e) {
  if (e - b < 2) return;  // also an empty bucket of an empty array: b may be null, and null + 1 is UB
  if (e - b > 24) {
    std::sort(b, e);
    return;
  }
  for (uint64_t* i = b + 1; i < e; ++i) {
    const uint64_t k = *i;
    uint64_t* j = i;
    while (j > b && *(j - 1) > k) {
      *j = *(j - 1);
      --j;
    }
    *j = k;
  }
}

EdgeIncidence build_edge_incidence(const Mesh& m) {
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  const int32_t* off = m.face_offsets.data();
  const int32_t* fv = m.face_vertices.data();
  const size_t nc = m.face_vertices.size();

  // Bucket the half-edges by their smaller endpoint.
  HostVector<int64_t> start(static_cast<size_t>(nv) + 1, 0);
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    for (int32_t c = off[f]; c < off[f + 1]; ++c) {
      const int32_t u = fv[c], w = fv[c + 1 == off[f + 1] ? off[f] : c + 1];
      if (u != w) ++start[static_cast<size_t>(std::min(u, w)) + 1];
    }
  }
  for (int32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  // Key = (larger endpoint, corner): sorting a bucket groups the copies of an edge and
  // keeps them in ascending corner (= face) order, which makes everything deterministic.
  HostVector<uint64_t> key(static_cast<size_t>(start[nv]));
  {
    HostVector<int64_t> pos(start.begin(), start.end() - 1);
    for (int32_t f = 0; f < nf; ++f) {
      cancel_point(f);
      for (int32_t c = off[f]; c < off[f + 1]; ++c) {
        const int32_t u = fv[c], w = fv[c + 1 == off[f + 1] ? off[f] : c + 1];
        if (u == w) continue;
        const int32_t lo = std::min(u, w), hi = std::max(u, w);
        key[pos[lo]++] = (static_cast<uint64_t>(hi) << 32) | static_cast<uint32_t>(c);
      }
    }
  }
  int64_t ne = 0;
  for (int32_t v = 0; v < nv; ++v) {
    cancel_point(v);
    uint64_t* b = key.data() + start[v];
    uint64_t* e = key.data() + start[v + 1];
    sort_bucket(b, e);
    for (uint64_t* k = b; k < e; ++k)
      if (k == b || (*k >> 32) != (*(k - 1) >> 32)) ++ne;
  }
  if (ne > std::numeric_limits<int32_t>::max())
    fail(ErrorCode::ResourceLimit, mesh_name(m) + ": more than 2^31-1 edges");

  EdgeIncidence inc;
  Edges& E = inc.edges;
  E.e0.resize(ne);
  E.e1.resize(ne);
  E.face_count.resize(ne);
  inc.corner_edge.assign(nc, -1);
  inc.edge_corner_offsets.resize(static_cast<size_t>(ne) + 1);
  inc.edge_corners.resize(key.size());
  int32_t id = -1;
  for (int32_t v = 0; v < nv; ++v) {
    cancel_point(v);
    for (int64_t p = start[v]; p < start[v + 1]; ++p) {
      const int32_t hi = static_cast<int32_t>(key[p] >> 32);
      const int32_t c = static_cast<int32_t>(key[p] & 0xffffffffu);
      if (p == start[v] || hi != static_cast<int32_t>(key[p - 1] >> 32)) {
        ++id;
        E.e0[id] = v;
        E.e1[id] = hi;
        E.face_count[id] = 0;
        inc.edge_corner_offsets[id] = p;
      }
      ++E.face_count[id];
      inc.corner_edge[c] = id;
      inc.edge_corners[p] = c;
    }
  }
  inc.edge_corner_offsets[ne] = static_cast<int64_t>(key.size());
  return inc;
}

}  // namespace

EdgeIncidence edge_incidence(const Mesh& m) {
  validate_mesh_arrays(m);
  return build_edge_incidence(m);
}

Edges unique_edges(const Mesh& m) { return edge_incidence(m).edges; }

void drop_edge_corners(EdgeIncidence& inc) {
  HostVector<int64_t>().swap(inc.edge_corner_offsets);
  HostVector<int32_t>().swap(inc.edge_corners);
}

EdgeCorners::EdgeCorners(const EdgeIncidence& inc) {
  const Edges& E = inc.edges;
  const size_t ne = E.e0.size();
  if (inc.edge_corner_offsets.size() == ne + 1) {
    offsets_ = inc.edge_corner_offsets.data();
    corners_ = inc.edge_corners.data();
    return;
  }
  own_offsets_.resize(ne + 1);
  own_offsets_[0] = 0;
  for (size_t e = 0; e < ne; ++e) own_offsets_[e + 1] = own_offsets_[e] + E.face_count[e];
  own_corners_.resize(static_cast<size_t>(own_offsets_[ne]));
  HostVector<int64_t> pos(own_offsets_.begin(), own_offsets_.end() - 1);
  const int32_t nc = static_cast<int32_t>(inc.corner_edge.size());
  for (int32_t c = 0; c < nc; ++c)
    if (inc.corner_edge[c] >= 0) own_corners_[pos[inc.corner_edge[c]]++] = c;
  offsets_ = own_offsets_.data();
  corners_ = own_corners_.data();
}

Adjacency vertex_adjacency(const Mesh& m, const Edges& E) {
  const int32_t nv = m.num_vertices();
  const size_t ne = E.e0.size();
  Adjacency A;
  A.offsets.assign(static_cast<size_t>(nv) + 1, 0);
  for (size_t e = 0; e < ne; ++e) {
    if (E.e0[e] < 0 || E.e1[e] >= nv || E.e0[e] >= E.e1[e])
      fail(ErrorCode::BadUsage, "vertex_adjacency: edge list does not belong to this mesh");
    ++A.offsets[E.e0[e] + 1];
    ++A.offsets[E.e1[e] + 1];
  }
  for (int32_t v = 0; v < nv; ++v) A.offsets[v + 1] += A.offsets[v];
  A.neighbors.resize(2 * ne);
  HostVector<int64_t> pos(A.offsets.begin(), A.offsets.end() - 1);
  // Edges are sorted by (e0, e1): first every vertex receives its smaller neighbors
  // (in ascending e0 order), then its larger ones (ascending e1), so each row is sorted.
  for (size_t e = 0; e < ne; ++e) A.neighbors[pos[E.e1[e]]++] = E.e0[e];
  for (size_t e = 0; e < ne; ++e) A.neighbors[pos[E.e0[e]]++] = E.e1[e];
  return A;
}

Adjacency vertex_adjacency(const Mesh& m) {
  validate_mesh_arrays(m);
  return vertex_adjacency(m, build_edge_incidence(m).edges);
}

std::vector<std::vector<int32_t>> boundary_loops(const Mesh& m, const EdgeIncidence& inc) {
  const int32_t nv = m.num_vertices();
  const Edges& E = inc.edges;
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  const int32_t* fv = m.face_vertices.data();
  // Tail of the single half-edge on each boundary edge (face direction).
  HostVector<int64_t> bstart(static_cast<size_t>(nv) + 1, 0);
  for (int64_t e = 0; e < ne; ++e)
    if (E.face_count[e] == 1) {
      ++bstart[E.e0[e] + 1];
      ++bstart[E.e1[e] + 1];
    }
  for (int32_t v = 0; v < nv; ++v) bstart[v + 1] += bstart[v];
  if (bstart[nv] == 0) return {};  // closed: no corner lists needed
  HostVector<int32_t> bedges(static_cast<size_t>(bstart[nv]));
  {
    HostVector<int64_t> pos(bstart.begin(), bstart.end() - 1);
    for (int64_t e = 0; e < ne; ++e)
      if (E.face_count[e] == 1) {
        bedges[pos[E.e0[e]]++] = static_cast<int32_t>(e);
        bedges[pos[E.e1[e]]++] = static_cast<int32_t>(e);
      }
  }
  const EdgeCorners corners(inc);
  // Corner c of a triangle mesh is corner c % 3 of face c / 3.
  const bool tri = m.is_triangle_mesh();
  auto tail_of = [&](int64_t e) {
    const int64_t c = corners.first(e);
    if (!tri) return fv[c];
    const int32_t f = static_cast<int32_t>(c / 3);
    return c % 3 == 0 ? m.f0[f] : c % 3 == 1 ? m.f1[f] : m.f2[f];
  };
  HostVector<char> used(static_cast<size_t>(ne), 0);
  std::vector<std::vector<int32_t>> loops;
  for (int64_t e = 0; e < ne; ++e) {
    if (E.face_count[e] != 1 || used[e]) continue;
    std::vector<int32_t> loop;
    const int32_t first = tail_of(e);
    loop.push_back(first);
    used[e] = 1;
    int32_t cur = E.e0[e] + E.e1[e] - first;
    while (cur != first) {
      loop.push_back(cur);
      int32_t next = -1, fallback = -1;
      for (int64_t p = bstart[cur]; p < bstart[cur + 1]; ++p) {
        const int32_t b = bedges[p];
        if (used[b]) continue;
        if (tail_of(b) == cur) {
          next = b;
          break;
        }
        if (fallback < 0) fallback = b;  // only with inconsistent orientation
      }
      if (next < 0) next = fallback;
      if (next < 0) break;  // open chain: possible only next to non-manifold edges
      used[next] = 1;
      cur = E.e0[next] + E.e1[next] - cur;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<std::vector<int32_t>> boundary_loops(const Mesh& m) {
  validate_mesh_arrays(m);
  return boundary_loops(m, build_edge_incidence(m));
}

int32_t connected_components(const Mesh& m, std::vector<int32_t>& component_of_vertex) {
  validate_mesh_arrays(m);
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  std::vector<int32_t> parent(static_cast<size_t>(nv));
  for (int32_t v = 0; v < nv; ++v) parent[v] = v;
  std::vector<char> referenced(static_cast<size_t>(nv), 0);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t b = m.face_offsets[f];
    for (int32_t c = b; c < m.face_offsets[f + 1]; ++c) {
      referenced[m.face_vertices[c]] = 1;
      uf_unite(parent, m.face_vertices[b], m.face_vertices[c]);
    }
  }
  component_of_vertex.assign(static_cast<size_t>(nv), -1);
  int32_t count = 0;
  // Ascending vertex order: a root is the smallest vertex of its set, so components are
  // numbered by their smallest vertex.
  for (int32_t v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    const int32_t r = uf_find(parent, v);
    if (r == v) component_of_vertex[v] = count++;
    else component_of_vertex[v] = component_of_vertex[r];
  }
  return count;
}

double mean_edge_length(const Mesh& m, const Edges& E) {
  const size_t ne = E.e0.size();
  if (ne == 0) return 0.0;
  double sum = 0.0;
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = E.e0[e], b = E.e1[e];
    sum += std::sqrt((m.x[a] - m.x[b]) * (m.x[a] - m.x[b]) + (m.y[a] - m.y[b]) * (m.y[a] - m.y[b]) +
                     (m.z[a] - m.z[b]) * (m.z[a] - m.z[b]));
  }
  return sum / static_cast<double>(ne);
}

double mean_edge_length(const Mesh& m) {
  validate_mesh_arrays(m);
  return mean_edge_length(m, build_edge_incidence(m).edges);
}

}  // namespace locus
