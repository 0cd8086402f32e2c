// Mesh validation: analyze_mesh (one pass report of counts, topology and first
// offenders) and check_requirements (what a pipeline needs, DESIGN.md "Input is
// hostile"). Genus from Euler's formula chi = V - E + F = 2 - 2g - b for a
// connected orientable surface with b boundary loops.
//
// Manifoldness is decided combinatorially: an edge is non-manifold when more than
// two faces share it, or when its two faces traverse it in the same direction
// (inconsistent orientation); a vertex is non-manifold when its incident faces
// split into more than one fan, i.e. when the corners at that vertex, joined
// across the manifold edges around it, form more than one union-find class.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "locus/core/host_allocator.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "mesh_topology_union_find.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/coordinate_range.hpp"

namespace locus {

namespace {

// Area of a polygon as half the norm of its vector area (exact for planar polygons;
// for a triangle the usual half cross product). Relative to the first vertex to
// limit cancellation far from the origin.
// Area of the face times sc^2 (sc: power_of_two_scale, so that tiny and huge
// meshes neither underflow nor overflow).
double face_area(const Mesh& m, int32_t b, int32_t e, double sc) {
  const int32_t* fv = m.face_vertices.data();
  const double ox = m.x[fv[b]], oy = m.y[fv[b]], oz = m.z[fv[b]];
  double ax = 0, ay = 0, az = 0;
  for (int32_t c = b + 1; c + 1 < e; ++c) {
    const double ux = (m.x[fv[c]] - ox) * sc, uy = (m.y[fv[c]] - oy) * sc, uz = (m.z[fv[c]] - oz) * sc;
    const double wx = (m.x[fv[c + 1]] - ox) * sc, wy = (m.y[fv[c + 1]] - oy) * sc, wz = (m.z[fv[c + 1]] - oz) * sc;
    ax += uy * wz - uz * wy;
    ay += uz * wx - ux * wz;
    az += ux * wy - uy * wx;
  }
  return 0.5 * std::sqrt(ax * ax + ay * ay + az * az);
}

// Face degree histogram and first non-triangle.
void count_faces(const Mesh& m, MeshReport& r) {
  const int32_t nf = m.num_faces();
  const int32_t* off = m.face_offsets.data();
  int32_t max_degree = 0;
  for (int32_t f = 0; f < nf; ++f) max_degree = std::max(max_degree, off[f + 1] - off[f]);
  r.face_degree_histogram.assign(static_cast<size_t>(max_degree) + 1, 0);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t d = off[f + 1] - off[f];
    ++r.face_degree_histogram[d];
    if (d != 3 && r.first_non_triangle_face < 0) r.first_non_triangle_face = f;
  }
}

// Unreferenced and non-finite vertices, bounding box; referenced[v] != 0 for
// vertices of some face. Returns how many are referenced.
int64_t count_vertices(const Mesh& m, MeshReport& r, std::vector<char>& referenced) {
  const int32_t nv = m.num_vertices();
  referenced.assign(static_cast<size_t>(nv), 0);
  for (int32_t v : m.face_vertices) referenced[v] = 1;
  int64_t n_referenced = 0;
  for (int32_t v = 0; v < nv; ++v) {
    if (referenced[v]) {
      ++n_referenced;
    } else {
      ++r.unreferenced_vertices;
      if (r.first_unreferenced_vertex < 0) r.first_unreferenced_vertex = v;
    }
  }
  for (int32_t v = 0; v < nv; ++v)
    if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v])) {
      ++r.non_finite_vertices;
      if (r.first_non_finite_vertex < 0) r.first_non_finite_vertex = v;
    }
  if (nv > 0) {
    const auto [xlo, xhi] = std::minmax_element(m.x.begin(), m.x.end());
    const auto [ylo, yhi] = std::minmax_element(m.y.begin(), m.y.end());
    const auto [zlo, zhi] = std::minmax_element(m.z.begin(), m.z.end());
    r.bbox_min[0] = *xlo; r.bbox_min[1] = *ylo; r.bbox_min[2] = *zlo;
    r.bbox_max[0] = *xhi; r.bbox_max[1] = *yhi; r.bbox_max[2] = *zhi;
  }
  return n_referenced;
}

// The face of corner c (for messages only: one binary search).
int32_t face_of_corner(const Mesh& m, int32_t c) {
  const auto it = std::upper_bound(m.face_offsets.begin(), m.face_offsets.end(), c);
  return static_cast<int32_t>(it - m.face_offsets.begin()) - 1;
}

// The first offender among the non-manifold edges: the one of smallest id.
void report_bad_edge(const Mesh& m, const EdgeIncidence& inc, int64_t e, MeshReport& r) {
  const EdgeCorners corners(inc);
  const int64_t p = corners.offsets()[e];
  r.first_non_manifold_edge_v0 = inc.edges.e0[e];
  r.first_non_manifold_edge_v1 = inc.edges.e1[e];
  r.first_non_manifold_edge_faces = inc.edges.face_count[e];
  r.first_non_manifold_edge_face_a = face_of_corner(m, corners.corners()[p]);
  r.first_non_manifold_edge_face_b = face_of_corner(m, corners.corners()[p + 1]);
}

// Every corner's two edges at its vertex (the half-edge arriving there, the one
// leaving; -1 for a degenerate one), bucketed by vertex in ascending corner order.
struct CornerEdges {
  HostVector<int64_t> start;                      // nv + 1
  HostVector<std::array<int32_t, 2>> in_out;      // per bucket slot
};

CornerEdges corner_edges_by_vertex(const Mesh& m, const EdgeIncidence& inc) {
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  const int32_t* off = m.face_offsets.data();
  const int32_t* fv = m.face_vertices.data();
  CornerEdges ce;
  ce.start.assign(static_cast<size_t>(nv) + 1, 0);
  for (const int32_t v : m.face_vertices) ++ce.start[static_cast<size_t>(v) + 1];
  for (int32_t v = 0; v < nv; ++v) ce.start[v + 1] += ce.start[v];
  ce.in_out.resize(m.face_vertices.size());
  HostVector<int64_t> pos(ce.start.begin(), ce.start.end() - 1);
  for (int32_t f = 0; f < nf; ++f)
    for (int32_t c = off[f], prev = off[f + 1] - 1; c < off[f + 1]; prev = c++)
      ce.in_out[pos[fv[c]]++] = {inc.corner_edge[prev], inc.corner_edge[c]};
  return ce;
}

// Insertion sort: a vertex has a dozen edge uses.
void sort_small(uint64_t* b, uint64_t* e) {
  if (b == e) return;  // an isolated vertex: b may be null, and null + 1 is undefined
  for (uint64_t* i = b + 1; i < e; ++i) {
    const uint64_t k = *i;
    uint64_t* j = i;
    for (; j > b && *(j - 1) > k; --j) *j = *(j - 1);
    *j = k;
  }
}

// Edges: boundary, non-manifold (> 2 faces or same direction twice); vertices
// whose faces form more than one fan; r.manifold.
//
// Vertex by vertex, over the corners at v only (a few, contiguous): an edge at
// v occurs among their in/out edges once per face on it, so its multiplicity
// there is its face count. The corners that share an edge of two faces are in
// one fan (whatever the orientation); the fans are the classes of a union-find
// over the vertex's own corners. At the edge's smaller end e0, its two
// occurrences must be one leaving (e0 -> e1) and one arriving, or both faces
// run it the same way. (One pass in face order, one in vertex order: this
// replaced a union-find over all corners in edge order, whose random reads
// made it 75% of analyze_mesh at 416k vertices.)
void check_manifold(const Mesh& m, const EdgeIncidence& inc, MeshReport& r) {
  const int32_t nv = m.num_vertices();
  const Edges& E = inc.edges;
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  int64_t first_bad = ne;
  const auto bad_edge = [&](int64_t e) {
    ++r.non_manifold_edges;
    first_bad = std::min(first_bad, e);
  };
  for (int64_t e = 0; e < ne; ++e) {
    if (E.face_count[e] == 1) ++r.boundary_edges;
    if (E.face_count[e] > 2) bad_edge(e);
  }
  const CornerEdges ce = corner_edges_by_vertex(m, inc);
  // Uses of an edge at one vertex, as (edge << 32 | corner slot << 1 | leaving);
  // the union-find over that vertex's corners.
  std::vector<uint64_t> uses;
  std::vector<int32_t> parent;
  int64_t owned = 0;  // E is sorted by e0: the edges of v as smaller end are next
  for (int32_t v = 0; v < nv; ++v) {
    const int64_t b = ce.start[v];
    const int32_t d = static_cast<int32_t>(ce.start[v + 1] - b);
    const int64_t owned_end = std::upper_bound(E.e0.begin() + owned, E.e0.end(), v) - E.e0.begin();
    uses.clear();
    for (int32_t i = 0; i < d; ++i)
      for (int leaving = 0; leaving < 2; ++leaving) {
        const int32_t e = ce.in_out[b + i][leaving];
        if (e >= 0) uses.push_back(static_cast<uint64_t>(e) << 32 | static_cast<uint64_t>(i) << 1 | leaving);
      }
    sort_small(uses.data(), uses.data() + uses.size());
    parent.resize(static_cast<size_t>(d));
    for (int32_t i = 0; i < d; ++i) parent[i] = i;
    int64_t fans = d;
    for (size_t g = 0; g < uses.size();) {
      const int64_t e = static_cast<int64_t>(uses[g] >> 32);
      size_t h = g + 1;
      while (h < uses.size() && static_cast<int64_t>(uses[h] >> 32) == e) ++h;
      if (h - g == 2) {
        const auto corner = [](uint64_t u) { return static_cast<int32_t>((u & 0xffffffffu) >> 1); };
        fans -= uf_unite(parent, corner(uses[g]), corner(uses[g + 1]));
        if (e >= owned && e < owned_end && (uses[g] & 1) == (uses[g + 1] & 1)) bad_edge(e);
      }
      g = h;
    }
    owned = owned_end;
    if (fans > 1) {
      ++r.non_manifold_vertices;
      if (r.first_non_manifold_vertex < 0) {
        r.first_non_manifold_vertex = v;
        r.first_non_manifold_vertex_fans = static_cast<int32_t>(fans);
      }
    }
  }
  if (first_bad < ne) report_bad_edge(m, inc, first_bad, r);
  r.manifold = r.non_manifold_edges == 0 && r.non_manifold_vertices == 0;
}

// Degenerate faces: (near-)zero area relative to the mesh scale, non-finite area, or
// a repeated consecutive vertex.
void count_degenerate_faces(const Mesh& m, const EdgeIncidence& inc, MeshReport& r) {
  const int32_t* off = m.face_offsets.data();
  const double sc = power_of_two_scale(r.mean_edge_length), hs = r.mean_edge_length * sc;
  const double threshold = kDegenerateAreaRelative * hs * hs;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    bool degenerate = !(face_area(m, off[f], off[f + 1], sc) > threshold);
    for (int32_t c = off[f]; c < off[f + 1] && !degenerate; ++c) degenerate = inc.corner_edge[c] < 0;
    if (degenerate) {
      ++r.degenerate_faces;
      if (r.first_degenerate_face < 0) r.first_degenerate_face = f;
    }
  }
}

// Components over referenced vertices.
int32_t count_components(int32_t nv, const Edges& E, const std::vector<char>& referenced) {
  std::vector<int32_t> parent(static_cast<size_t>(nv));
  for (int32_t v = 0; v < nv; ++v) parent[v] = v;
  for (size_t e = 0; e < E.e0.size(); ++e) uf_unite(parent, E.e0[e], E.e1[e]);
  int32_t components = 0;
  for (int32_t v = 0; v < nv; ++v)
    if (referenced[v] && uf_find(parent, v) == v) ++components;
  return components;
}

}  // namespace

MeshReport analyze_mesh(const Mesh& m) {
  validate_mesh_arrays(m);
  return analyze_mesh(m, edge_incidence(m));
}

MeshReport analyze_mesh(const Mesh& m, const EdgeIncidence& inc) {
  validate_mesh_arrays(m);
  if (inc.corner_edge.size() != m.face_vertices.size())
    fail(ErrorCode::BadUsage, "analyze_mesh: the edge incidence belongs to another mesh");
  MeshReport r;
  const int32_t nv = m.num_vertices(), nf = m.num_faces();
  r.n_vertices = nv;
  r.n_faces = nf;
  count_faces(m, r);
  std::vector<char> referenced;
  const int64_t n_referenced = count_vertices(m, r, referenced);

  const int64_t ne = static_cast<int64_t>(inc.edges.e0.size());
  r.n_edges = ne;
  r.mean_edge_length = mean_edge_length(m, inc.edges);
  check_manifold(m, inc, r);
  count_degenerate_faces(m, inc, r);
  r.components = count_components(nv, inc.edges, referenced);

  const auto loops = boundary_loops(m, inc);
  r.boundary_loops = static_cast<int32_t>(loops.size());
  if (!loops.empty()) r.first_boundary_vertex = loops[0][0];

  r.euler_characteristic = n_referenced - ne + nf;
  const int64_t twice_genus = 2 - r.euler_characteristic - r.boundary_loops;
  r.genus = (r.components == 1 && r.manifold && twice_genus >= 0 && twice_genus % 2 == 0) ? twice_genus / 2 : -1;
  return r;
}

void check_requirements(const Mesh& m, const MeshRequirements& req, const MeshReport& r) {
  const std::string name = mesh_name(m);
  auto bad = [&](const std::string& what) { fail(ErrorCode::BadInput, name + ": " + what); };
  if (req.finite_coordinates && r.first_non_finite_vertex >= 0)
    bad("vertex " + std::to_string(r.first_non_finite_vertex) + " has a non-finite coordinate");
  // Before the degenerate faces: at sizes whose areas overflow or underflow every face looks degenerate.
  if (req.finite_coordinates && r.non_finite_vertices == 0)
    check_mesh_size(m, bounding_box_diagonal(r.bbox_min, r.bbox_max));
  if (req.triangles && r.first_non_triangle_face >= 0) {
    const int64_t f = r.first_non_triangle_face;
    const int32_t d = m.face_offsets[f + 1] - m.face_offsets[f];
    bad("face " + std::to_string(f) + " has " + std::to_string(d) + " vertices; this pipeline needs triangles");
  }
  if (req.no_unreferenced_vertices && r.first_unreferenced_vertex >= 0)
    bad("vertex " + std::to_string(r.first_unreferenced_vertex) + " is not referenced by any face");
  if (req.no_degenerate_faces && r.first_degenerate_face >= 0)
    bad("face " + std::to_string(r.first_degenerate_face) + " has zero area");
  if (req.manifold && r.first_non_manifold_edge_v0 >= 0) {
    const std::string edge =
        "edge (" + std::to_string(r.first_non_manifold_edge_v0) + ", " + std::to_string(r.first_non_manifold_edge_v1) + ")";
    if (r.first_non_manifold_edge_faces > 2)
      bad(edge + " is shared by " + std::to_string(r.first_non_manifold_edge_faces) + " faces (non-manifold)");
    bad(edge + " is traversed in the same direction by faces " + std::to_string(r.first_non_manifold_edge_face_a) +
        " and " + std::to_string(r.first_non_manifold_edge_face_b) + " (inconsistent orientation)");
  }
  if (req.manifold && r.first_non_manifold_vertex >= 0)
    bad("vertex " + std::to_string(r.first_non_manifold_vertex) + " is non-manifold (its faces form " +
        std::to_string(r.first_non_manifold_vertex_fans) + " separate fans)");
  if (req.connected && r.components != 1)
    bad("mesh has " + std::to_string(r.components) + " connected components; this pipeline needs a connected mesh");
  if (req.closed && r.boundary_edges > 0)
    bad("mesh has " + std::to_string(r.boundary_loops) + " boundary loop" + (r.boundary_loops == 1 ? "" : "s") +
        " (one through vertex " + std::to_string(r.first_boundary_vertex) + "); this pipeline needs a closed mesh");
}

void check_requirements(const Mesh& m, const MeshRequirements& req) {
  check_requirements(m, req, analyze_mesh(m));
}

}  // namespace locus
