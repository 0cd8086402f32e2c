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
#include <cmath>
#include <limits>
#include <string>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "mesh_topology_union_find.hpp"
#include "locus/error.hpp"

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

// Face degree histogram and first non-triangle; corner_face[c] = face of corner c.
void count_faces(const Mesh& m, MeshReport& r, std::vector<int32_t>& corner_face) {
  const int32_t nf = m.num_faces();
  const int32_t* off = m.face_offsets.data();
  int32_t max_degree = 0;
  for (int32_t f = 0; f < nf; ++f) max_degree = std::max(max_degree, off[f + 1] - off[f]);
  r.face_degree_histogram.assign(static_cast<size_t>(max_degree) + 1, 0);
  corner_face.resize(m.face_vertices.size());
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t d = off[f + 1] - off[f];
    ++r.face_degree_histogram[d];
    if (d != 3 && r.first_non_triangle_face < 0) r.first_non_triangle_face = f;
    for (int32_t c = off[f]; c < off[f + 1]; ++c) corner_face[c] = f;
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

// Edges: boundary, non-manifold (> 2 faces or same direction twice), and the
// corner unions that decide the fans around each vertex; then the vertices
// with more than one fan, and r.manifold.
void check_manifold(const Mesh& m, const EdgeIncidence& inc, const std::vector<int32_t>& corner_face, MeshReport& r) {
  const int32_t nv = m.num_vertices();
  const int32_t* off = m.face_offsets.data();
  const int32_t* fv = m.face_vertices.data();
  const size_t nc = m.face_vertices.size();
  const Edges& E = inc.edges;
  const int64_t ne = static_cast<int64_t>(E.e0.size());
  auto next_corner = [&](int32_t c) {
    const int32_t f = corner_face[c];
    return c + 1 == off[f + 1] ? off[f] : c + 1;
  };
  // fans[v] starts at the number of corners at v; every union that joins two of its
  // classes removes one.
  std::vector<int32_t> corner_parent(nc);
  for (size_t c = 0; c < nc; ++c) corner_parent[c] = static_cast<int32_t>(c);
  std::vector<int32_t> fans(static_cast<size_t>(nv), 0);
  for (size_t c = 0; c < nc; ++c) ++fans[fv[c]];
  for (int64_t e = 0; e < ne; ++e) {
    const int32_t fc = E.face_count[e];
    const int64_t p = inc.edge_corner_offsets[e];
    if (fc == 1) {
      ++r.boundary_edges;
      continue;
    }
    bool bad = fc > 2;
    if (fc == 2) {
      const int32_t c1 = inc.edge_corners[p], c2 = inc.edge_corners[p + 1];
      bad = fv[c1] == fv[c2];  // both half-edges start at the same end
      // Join the corners of the two faces at each end of the edge (the faces are then
      // in the same fan of that vertex), whatever their orientation.
      const int32_t u = E.e0[e];
      const int32_t u1 = fv[c1] == u ? c1 : next_corner(c1), w1 = fv[c1] == u ? next_corner(c1) : c1;
      const int32_t u2 = fv[c2] == u ? c2 : next_corner(c2), w2 = fv[c2] == u ? next_corner(c2) : c2;
      fans[u] -= uf_unite(corner_parent, u1, u2);
      fans[E.e1[e]] -= uf_unite(corner_parent, w1, w2);
    }
    if (bad) {
      ++r.non_manifold_edges;
      if (r.first_non_manifold_edge_v0 < 0) {
        r.first_non_manifold_edge_v0 = E.e0[e];
        r.first_non_manifold_edge_v1 = E.e1[e];
        r.first_non_manifold_edge_faces = fc;
        r.first_non_manifold_edge_face_a = corner_face[inc.edge_corners[p]];
        r.first_non_manifold_edge_face_b = corner_face[inc.edge_corners[p + 1]];
      }
    }
  }
  for (int32_t v = 0; v < nv; ++v)
    if (fans[v] > 1) {
      ++r.non_manifold_vertices;
      if (r.first_non_manifold_vertex < 0) {
        r.first_non_manifold_vertex = v;
        r.first_non_manifold_vertex_fans = fans[v];
      }
    }
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
  std::vector<int32_t> corner_face;
  count_faces(m, r, corner_face);
  std::vector<char> referenced;
  const int64_t n_referenced = count_vertices(m, r, referenced);

  const int64_t ne = static_cast<int64_t>(inc.edges.e0.size());
  r.n_edges = ne;
  r.mean_edge_length = mean_edge_length(m, inc.edges);
  check_manifold(m, inc, corner_face, r);
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
