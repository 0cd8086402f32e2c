// The edge incidence set aside and rebuilt (incidence_loan.hpp; thesis §3.7.1).
#include "incidence_loan.hpp"

#include <algorithm>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

namespace {

// edge_incidence(m) without its edge-to-corner CSR, from the vertex adjacency
// d already holds (vertex_adjacency of the same edges): the edges are each
// vertex's larger neighbors in ascending order, which is unique_edges' order,
// and a corner finds its edge by a binary search in its smaller end's row.
// Its transient memory is one n-vector, where edge_incidence sorts a key per
// corner and builds the CSR beside the result (~70 MB at 416k vertices, at a
// point of the remesh where the factor is still held). A triangle mesh's
// corners come from f0/f1/f2: its face_vertices may be lent out until the
// repair is done (face_corner_loan.hpp).
EdgeIncidence incidence_from_adjacency(const Mesh& m, const Adjacency& adj) {
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  HostVector<int64_t> first_edge(static_cast<size_t>(nv) + 1, 0);  // of each vertex as the smaller end
  for (int32_t v = 0; v < nv; ++v) {
    const int32_t* row = adj.neighbors.data() + adj.offsets[v];
    const int32_t* end = adj.neighbors.data() + adj.offsets[v + 1];
    first_edge[v + 1] = first_edge[v] + (end - std::upper_bound(row, end, v));
  }
  EdgeIncidence inc;
  Edges& E = inc.edges;
  const int64_t ne = first_edge[nv];
  E.e0.resize(static_cast<size_t>(ne));
  E.e1.resize(static_cast<size_t>(ne));
  E.face_count.assign(static_cast<size_t>(ne), 0);
  for (int32_t v = 0; v < nv; ++v) {
    const int32_t* end = adj.neighbors.data() + adj.offsets[v + 1];
    const int32_t* up = std::upper_bound(adj.neighbors.data() + adj.offsets[v], end, v);
    for (int64_t e = first_edge[v]; e < first_edge[v + 1]; ++e, ++up) {
      E.e0[e] = v;
      E.e1[e] = *up;
    }
  }
  const int32_t* off = m.face_offsets.data();
  const int32_t* fv = m.face_vertices.data();
  inc.corner_edge.assign(static_cast<size_t>(off[nf]), -1);  // face_vertices may be out: its size
  auto corner = [&](int32_t c, int32_t u, int32_t w) {
    if (u == w) return;
    const int32_t lo = std::min(u, w), hi = std::max(u, w);
    const int32_t* end = adj.neighbors.data() + adj.offsets[lo + 1];
    const int32_t* up = std::upper_bound(adj.neighbors.data() + adj.offsets[lo], end, lo);
    const int64_t e = first_edge[lo] + (std::lower_bound(up, end, hi) - up);
    inc.corner_edge[c] = static_cast<int32_t>(e);
    ++E.face_count[e];
  };
  if (m.is_triangle_mesh()) {  // corner off[f] + k of f0/f1/f2 (face_corner_loan.hpp: the corners may be out)
    for (int32_t f = 0; f < nf; ++f) {
      const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
      for (int k = 0; k < 3; ++k) corner(off[f] + k, v[k], v[(k + 1) % 3]);
    }
    return inc;
  }
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t c = off[f]; c < off[f + 1]; ++c) corner(c, fv[c], fv[c + 1 == off[f + 1] ? off[f] : c + 1]);
  return inc;
}

// vertex_adjacency(m) from the faces alone (the incidence is out too; of a
// triangle mesh from f0/f1/f2, its corners may be out as well): each
// half-edge's ends, counted, filled, then each row sorted and its repeats
// dropped, which leaves the neighbors of unique_edges' edges in ascending
// order, as vertex_adjacency(m, edges) lists them. Transient: the rows with
// repeats (two per corner, ~20 MB at 416k vertices), after the factorization
// has freed far more.
Adjacency adjacency_from_faces(const Mesh& m) {
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  const int32_t* off = m.face_offsets.data();
  const int32_t* fv = m.face_vertices.data();
  Adjacency A;
  A.offsets.assign(static_cast<size_t>(nv) + 1, 0);
  const bool triangles = m.is_triangle_mesh();  // face_vertices may be lent out (face_corner_loan.hpp)
  auto each_half_edge = [&](auto&& visit) {
    if (triangles) {  // the same half-edges in the same order as face_vertices'
      for (int32_t f = 0; f < nf; ++f) {
        const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
        for (int k = 0; k < 3; ++k)
          if (v[k] != v[(k + 1) % 3]) visit(v[k], v[(k + 1) % 3]);
      }
      return;
    }
    for (int32_t f = 0; f < nf; ++f)
      for (int32_t c = off[f]; c < off[f + 1]; ++c) {
        const int32_t u = fv[c], w = fv[c + 1 == off[f + 1] ? off[f] : c + 1];
        if (u != w) visit(u, w);
      }
  };
  each_half_edge([&](int32_t u, int32_t w) { ++A.offsets[u + 1], ++A.offsets[w + 1]; });
  for (int32_t v = 0; v < nv; ++v) A.offsets[v + 1] += A.offsets[v];
  HostVector<int32_t> rows(static_cast<size_t>(A.offsets[nv]));
  {
    HostVector<int64_t> pos(A.offsets.begin(), A.offsets.end() - 1);
    each_half_edge([&](int32_t u, int32_t w) { rows[pos[u]++] = w, rows[pos[w]++] = u; });
  }
  int64_t out = 0;
  for (int32_t v = 0; v < nv; ++v) {  // compacted in place: row v starts at or before where it was
    int32_t* begin = rows.data() + A.offsets[v];
    int32_t* end = rows.data() + A.offsets[v + 1];
    std::sort(begin, end);
    end = std::unique(begin, end);
    A.offsets[v] = out;
    for (const int32_t* w = begin; w < end; ++w) rows[out++] = *w;
  }
  A.offsets[nv] = out;
  A.neighbors = HostVector<int32_t>(rows.begin(), rows.begin() + out);
  return A;
}

}  // namespace

IncidenceLoan::~IncidenceLoan() {
  try {
    restore();
  } catch (...) {  // out of memory while unwinding: the owner's incidence stays empty
  }
}

void IncidenceLoan::release_adjacency() {
  if (adjacency_out_) return;
  d_.adjacency = Adjacency{};
  adjacency_out_ = true;
}

void IncidenceLoan::restore_adjacency() {
  if (!adjacency_out_) return;
  d_.adjacency = adjacency_from_faces(m_);
  adjacency_out_ = false;
}

void IncidenceLoan::release() {
  if (released_) return;
  had_corners_ = !d_.incidence.edge_corner_offsets.empty();
  d_.incidence = EdgeIncidence{};
  released_ = true;
}

void IncidenceLoan::restore() {
  restore_adjacency();  // the incidence is rebuilt from it
  if (!released_) return;
  d_.incidence = had_corners_ ? edge_incidence(m_) : incidence_from_adjacency(m_, d_.adjacency);
  released_ = false;
}

}  // namespace locus
