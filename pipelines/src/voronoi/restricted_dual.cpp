// Restricted-Delaunay dual of a vertex-labelled partition and its closed-ball
// checks (pipelines/include/locus/pipelines/voronoi/restricted_dual.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/restricted_dual.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include "locus/error.hpp"

namespace locus {

namespace {

struct Dsu {
  std::vector<int32_t> parent, size;
  explicit Dsu(int32_t n) : parent(n), size(n, 1) { std::iota(parent.begin(), parent.end(), 0); }
  int32_t find(int32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(int32_t a, int32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size[a] < size[b] || (size[a] == size[b] && b < a)) std::swap(a, b);
    parent[b] = a;
    size[a] += size[b];
  }
};

double dist2(const Mesh& m, int32_t v, const std::array<double, 3>& p) {
  const double dx = m.x[v] - p[0], dy = m.y[v] - p[1], dz = m.z[v] - p[2];
  return dx * dx + dy * dy + dz * dz;
}

// Collects repair vertices: one per defect, each vertex once, none at a vertex site.
struct Repairs {
  std::vector<uint8_t> taken;
  std::vector<int32_t>& out;
  const Edges& edges;
  bool near = false;         // add_near may look beyond the defect's own vertex
  std::vector<int64_t> off;  // vertex adjacency (CSR), built at the first add_near that needs it
  std::vector<int32_t> nbr;
  // The first untaken of the candidates (a defect may sit next to a site that
  // an earlier round put on a vertex).
  bool add(int32_t v) {
    if (taken[v]) return false;
    taken[v] = 1;
    out.push_back(v);
    return true;
  }
  void add(int32_t v, int32_t alt) {
    if (!add(v) && !add(alt)) add_near(v);
  }
  // v, else the nearest untaken vertex within three rings of it (breadth
  // first): where the cells span few vertices every vertex of a defect may
  // hold a site already, and a site next to it still splits the region.
  void add_near(int32_t v) {
    if (add(v) || !near) return;
    if (off.empty()) build();
    std::vector<int32_t> ring{v}, seen{v};
    for (int r = 0; r < 3; ++r) {
      std::vector<int32_t> next;
      for (int32_t a : ring)
        for (int64_t p = off[a]; p < off[a + 1]; ++p) {
          const int32_t b = nbr[p];
          if (std::find(seen.begin(), seen.end(), b) != seen.end()) continue;
          if (add(b)) return;
          seen.push_back(b);
          next.push_back(b);
        }
      ring = std::move(next);
    }
  }
  void build() {
    const size_t n = taken.size();
    off.assign(n + 1, 0);
    for (size_t k = 0; k < edges.e0.size(); ++k) ++off[edges.e0[k] + 1], ++off[edges.e1[k] + 1];
    for (size_t v = 0; v < n; ++v) off[v + 1] += off[v];
    nbr.resize(static_cast<size_t>(off[n]));
    std::vector<int64_t> fill(off.begin(), off.end() - 1);
    for (size_t k = 0; k < edges.e0.size(); ++k) {
      nbr[fill[edges.e0[k]]++] = edges.e1[k];
      nbr[fill[edges.e1[k]]++] = edges.e0[k];
    }
  }
};

// Cells: K_A connected with Euler characteristic 1.
void check_cells(const Mesh& m, const DualTopology& topo, std::span<const int32_t> label,
                 std::span<const SurfacePoint> sites, RestrictedDual& d, Repairs& rep) {
  const int32_t n = m.num_vertices(), ns = static_cast<int32_t>(sites.size());
  const Edges& e = topo.inc().edges;
  std::vector<int64_t> chi(ns, 0);
  d.cell_size.assign(ns, 0);
  for (int32_t v = 0; v < n; ++v) ++d.cell_size[label[v]];
  for (int32_t s = 0; s < ns; ++s) chi[s] = d.cell_size[s];
  Dsu vd(n);
  for (size_t k = 0; k < e.e0.size(); ++k)
    if (label[e.e0[k]] == label[e.e1[k]]) {
      --chi[label[e.e0[k]]];
      vd.unite(e.e0[k], e.e1[k]);
    }
  for (int32_t f = 0; f < m.num_faces(); ++f)
    if (label[m.f0[f]] == label[m.f1[f]] && label[m.f1[f]] == label[m.f2[f]]) ++chi[label[m.f0[f]]];
  std::vector<int32_t> pieces(ns, 0), smallest(ns, -1);
  for (int32_t v = 0; v < n; ++v)
    if (vd.find(v) == v) {
      const int32_t s = label[v];
      ++pieces[s];
      if (smallest[s] < 0 || vd.size[v] < vd.size[smallest[s]]) smallest[s] = v;
    }
  std::vector<int32_t> farthest(ns, -1);
  std::vector<double> far_d(ns, -1.0);
  std::vector<std::array<double, 3>> pos(ns);
  bool any_non_disk = false;
  for (int32_t s = 0; s < ns; ++s) {
    if (pieces[s] > 1) {
      ++d.defects.split_cells;
      rep.add_near(smallest[s]);
    } else if (pieces[s] == 1 && chi[s] != 1) {
      ++d.defects.non_disk_cells;
      any_non_disk = true;
      pos[s] = surface_point_position(m, sites[s]);
    }
  }
  if (!any_non_disk) return;
  // A non-disk cell (around a handle, or holding another cell or a whole
  // component) is split by a site at its vertex farthest from its site.
  for (int32_t v = 0; v < n; ++v) {
    const int32_t s = label[v];
    if (pieces[s] != 1 || chi[s] == 1) continue;
    const double dd = dist2(m, v, pos[s]);
    if (dd > far_d[s]) {
      far_d[s] = dd;
      farthest[s] = v;
    }
  }
  for (int32_t s = 0; s < ns; ++s)
    if (farthest[s] >= 0) rep.add_near(farthest[s]);
}

// Interfaces: per pair of labels, the chains of two-label edges linked through
// two-label faces; endpoints are corners (three-label faces) and boundary edges.
// The lists are over the two-label edges only, in edge order (~8 MB with
// their index by smaller end, instead of ~22 MB at 416k vertices);
// the union-find sees the same unions in the same index order, so its roots
// are the same edges.
void check_interfaces(const Mesh& m, const DualTopology& topo, std::span<const int32_t> label, RestrictedDual& d,
                      Repairs& rep) {
  const Edges& e = topo.inc().edges;
  const int32_t ne = static_cast<int32_t>(e.e0.size());
  HostVector<int32_t> cut;  // the two-label edges, ascending
  for (int32_t k = 0; k < ne; ++k)
    if (label[e.e0[k]] != label[e.e1[k]]) cut.push_back(k);
  // cut[first[v] .. first[v + 1]) are those whose smaller end is v (edges
  // sort by it): a corner's edge is found among its end's few.
  HostVector<int32_t> first(static_cast<size_t>(m.num_vertices()) + 1, 0);
  for (int32_t k : cut) ++first[e.e0[k] + 1];
  for (int32_t v = 0; v < m.num_vertices(); ++v) first[v + 1] += first[v];
  auto slot = [&](int32_t k) {
    int32_t i = first[e.e0[k]];
    while (cut[i] != k) ++i;
    return i;
  };
  const int32_t ni = static_cast<int32_t>(cut.size());
  Dsu ed(ni);
  std::vector<uint8_t> corner_ends(ni, 0);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t off = m.face_offsets[f];
    const int32_t l[3] = {label[m.f0[f]], label[m.f1[f]], label[m.f2[f]]};
    if (l[0] == l[1] && l[1] == l[2]) continue;
    const int32_t* ee = topo.inc().corner_edge.data() + off;
    if (l[0] != l[1] && l[1] != l[2] && l[0] != l[2]) {
      for (int k = 0; k < 3; ++k) ++corner_ends[slot(ee[k])];
      continue;
    }
    int32_t pair[2], np = 0;  // the two edges whose ends differ
    for (int k = 0; k < 3; ++k)
      if (l[k] != l[(k + 1) % 3]) pair[np++] = slot(ee[k]);
    ed.unite(pair[0], pair[1]);
  }
  std::vector<int32_t> corners(ni, 0), bends(ni, 0);
  for (int32_t i = 0; i < ni; ++i) {
    const int32_t r = ed.find(i);
    corners[r] += corner_ends[i];
    bends[r] += e.face_count[cut[i]] == 1;
  }
  std::vector<std::tuple<int32_t, int32_t, int32_t, int32_t>> comp;  // (a, b, -size, root)
  for (int32_t i = 0; i < ni; ++i) {
    const int32_t a = label[e.e0[cut[i]]], b = label[e.e1[cut[i]]];
    if (ed.find(i) == i) comp.emplace_back(std::min(a, b), std::max(a, b), -ed.size[i], i);
  }
  std::sort(comp.begin(), comp.end());
  for (size_t i = 0; i < comp.size(); ++i) {
    const int32_t r = std::get<3>(comp[i]);
    const bool extra = i > 0 && std::get<0>(comp[i]) == std::get<0>(comp[i - 1]) &&
                       std::get<1>(comp[i]) == std::get<1>(comp[i - 1]);
    bool bad = extra;
    if (extra) ++d.defects.split_interfaces;
    if (corners[r] + bends[r] == 0) {
      ++d.defects.loop_interfaces;
      bad = true;
    } else if (corners[r] == 0) {
      ++d.defects.boundary_interfaces;
      bad = true;
    }
    if (bad) rep.add(e.e0[cut[r]], e.e1[cut[r]]);
  }
}

// Corners: one face per label triple.
void check_corners(const Mesh& m, std::span<const int32_t> label, RestrictedDual& d, Repairs& rep) {
  std::vector<std::array<int32_t, 4>> tri;  // sorted labels, face
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    std::array<int32_t, 3> l = {label[m.f0[f]], label[m.f1[f]], label[m.f2[f]]};
    if (l[0] == l[1] || l[1] == l[2] || l[0] == l[2]) continue;
    std::sort(l.begin(), l.end());
    tri.push_back({l[0], l[1], l[2], f});
  }
  std::sort(tri.begin(), tri.end());
  for (size_t i = 1; i < tri.size(); ++i)
    if (tri[i][0] == tri[i - 1][0] && tri[i][1] == tri[i - 1][1] && tri[i][2] == tri[i - 1][2]) {
      ++d.defects.repeated_corners;
      const bool first_extra = i < 2 || tri[i - 2][0] != tri[i][0] || tri[i - 2][1] != tri[i][1] ||
                               tri[i - 2][2] != tri[i][2];
      if (first_extra) rep.add_near(m.f0[tri[i][3]]);
    }
}

// Boundary: one run per cell over all loops, at least three runs per loop; the
// dual vertex of a boundary cell moves to its run's sharpest corner or nearest vertex.
void check_boundary(const Mesh& m, const DualTopology& topo, std::span<const int32_t> label,
                    std::span<const SurfacePoint> sites, RestrictedDual& d, Repairs& rep) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  d.boundary_vertex.assign(ns, -1);
  std::vector<int32_t> runs_of(ns, 0);
  std::vector<double> best(ns, INFINITY);
  for (const std::vector<int32_t>& loop : topo.loops) {
    const size_t len = loop.size();
    if (len == 0) continue;
    size_t start = 0;  // a position where the label changes (0 if none)
    for (size_t i = 0; i < len; ++i)
      if (label[loop[i]] != label[loop[(i + len - 1) % len]]) {
        start = i;
        break;
      }
    size_t runs = 0, longest = 0, longest_mid = 0;
    for (size_t i = 0; i < len;) {
      const int32_t s = label[loop[(start + i) % len]];
      size_t j = i;
      while (j < len && label[loop[(start + j) % len]] == s) ++j;
      ++runs;
      if (j - i > longest) {
        longest = j - i;
        longest_mid = (start + (i + j) / 2) % len;
      }
      if (++runs_of[s] > 1) {
        ++d.defects.split_boundary_runs;
        rep.add_near(loop[(start + (i + j) / 2) % len]);
      } else {
        const auto p = surface_point_position(m, sites[s]);
        for (size_t k = i; k < j; ++k) {  // sharp corners first (key < 0), then nearest
          const int32_t v = loop[(start + k) % len];
          const double key = topo.sharp_boundary[v] ? -1.0 / (1.0 + dist2(m, v, p)) : dist2(m, v, p);
          if (key < best[s]) {
            best[s] = key;
            d.boundary_vertex[s] = v;
          }
        }
      }
      i = j;
    }
    if (runs < 3) {  // sites a third of the loop apart (small holes need one per vertex)
      ++d.defects.short_boundary_loops;
      for (size_t k = 0; k < 3 && k < len; ++k) rep.add(loop[(longest_mid + k * len / 3) % len]);
    }
  }
}

}  // namespace

namespace {

// Seams: a tube cut along a line, the cut's vertices duplicated, has one loop
// that runs along the cut twice (vertices at one position, and a neighbor of
// each at another shared position). The 90-degree turns at the seam's ends are
// the cut's, not the surface's: snapping dual vertices to both ends of a seam
// puts them on one line (zero-area remesh triangles), so they are not sharp.
// A loop touching itself at one point only (a pinch) and loops of different
// components that touch (CAD patches) keep their corners.
void clear_seam_ends(const Mesh& m, DualTopology& t) {
  auto same = [&m](int32_t p, int32_t q) { return m.x[p] == m.x[q] && m.y[p] == m.y[q] && m.z[p] == m.z[q]; };
  for (const auto& loop : t.loops) {
    const size_t len = loop.size();
    std::vector<size_t> at(len);  // loop positions sorted by vertex position
    std::iota(at.begin(), at.end(), size_t{0});
    auto key = [&](size_t i) { return std::make_tuple(m.x[loop[i]], m.y[loop[i]], m.z[loop[i]], i); };
    std::sort(at.begin(), at.end(), [&](size_t i, size_t j) { return key(i) < key(j); });
    for (size_t k = 0; k < len; ++k)
      for (size_t l = k + 1; l < len && same(loop[at[k]], loop[at[l]]); ++l) {
        const size_t i = at[k], j = at[l];
        if (loop[i] == loop[j]) continue;
        bool seam = false;
        for (size_t di : {size_t{1}, len - 1})
          for (size_t dj : {size_t{1}, len - 1}) seam = seam || same(loop[(i + di) % len], loop[(j + dj) % len]);
        if (seam) t.sharp_boundary[loop[i]] = t.sharp_boundary[loop[j]] = 0;
      }
  }
}

// Loops and sharp boundary corners of t.inc().
void complete_topology(const Mesh& m, DualTopology& t) {
  t.loops = boundary_loops(m, t.inc());
  t.sharp_boundary.assign(m.num_vertices(), 0);
  for (const auto& loop : t.loops) {
    const size_t len = loop.size();
    for (size_t i = 0; i < len; ++i) {
      const int32_t a = loop[(i + len - 1) % len], v = loop[i], b = loop[(i + 1) % len];
      const double u[3] = {m.x[v] - m.x[a], m.y[v] - m.y[a], m.z[v] - m.z[a]};
      const double w[3] = {m.x[b] - m.x[v], m.y[b] - m.y[v], m.z[b] - m.z[v]};
      const double c = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
      const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      const double nw = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      // Turning angle above 45 degrees: cos below 1/sqrt(2).
      if (nu > 0 && nw > 0 && c < std::sqrt(0.5) * nu * nw) t.sharp_boundary[v] = 1;
    }
  }
  clear_seam_ends(m, t);
}

void check_triangles(const Mesh& m) {
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": the restricted dual needs a triangle mesh");
}

}  // namespace

DualTopology dual_topology(const Mesh& m) {
  check_triangles(m);
  DualTopology t;
  t.own = edge_incidence(m);
  complete_topology(m, t);
  return t;
}

DualTopology dual_topology(const Mesh& m, const EdgeIncidence& inc) {
  check_triangles(m);
  if (inc.corner_edge.size() != static_cast<size_t>(m.face_offsets.back()))  // face_vertices may be lent out
    fail(ErrorCode::BadUsage, "dual topology: the edge incidence belongs to another mesh");
  DualTopology t;
  t.borrowed = &inc;
  complete_topology(m, t);
  return t;
}

RestrictedDual restricted_dual(const Mesh& m, const DualTopology& topo, std::span<const int32_t> label,
                               std::span<const SurfacePoint> sites) {
  const int32_t n = m.num_vertices(), ns = static_cast<int32_t>(sites.size());
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": the restricted dual needs a triangle mesh");
  if (label.size() != static_cast<size_t>(n) || topo.sharp_boundary.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "restricted dual: one label per vertex and the mesh's own topology expected");
  for (int32_t v = 0; v < n; ++v)
    if (label[v] < 0 || label[v] >= ns)
      fail(ErrorCode::BadUsage, "restricted dual: vertex " + std::to_string(v) + " has label " +
                                    std::to_string(label[v]) + ", outside 0.." + std::to_string(ns - 1));
  RestrictedDual d;
  // The defects' own vertices first; only when none of them is free, their
  // neighborhoods (Repairs::add_near).
  for (bool near : {false, true}) {
    d = RestrictedDual{};
    Repairs rep{std::vector<uint8_t>(n, 0), d.repair_vertices, topo.inc().edges, near, {}, {}};
    for (const SurfacePoint& p : sites) {  // a site at a vertex (or at a face's corner) takes it
      if (p.face < 0 && p.vertex >= 0 && p.vertex < n) rep.taken[p.vertex] = 1;
      if (p.face >= 0) {  // f0/f1/f2: the caller may have lent face_vertices out (cvt_remesh.hpp)
        const int32_t fv[3] = {m.f0[p.face], m.f1[p.face], m.f2[p.face]};
        for (int k = 0; k < 3; ++k)
          if (p.bary[k] >= 1 - 1e-9) rep.taken[fv[k]] = 1;
      }
    }
    check_cells(m, topo, label, sites, d, rep);
    check_interfaces(m, topo, label, d, rep);
    check_corners(m, label, d, rep);
    check_boundary(m, topo, label, sites, d, rep);
    if (d.defects.total() == 0 || !d.repair_vertices.empty()) break;
  }
  if (d.defects.total() > 0) return d;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t a = label[m.f0[f]], b = label[m.f1[f]], c = label[m.f2[f]];
    if (a == b || b == c || a == c) continue;
    d.triangles.push_back({a, b, c});
    d.corner_face.push_back(f);
  }
  return d;
}

Mesh dual_mesh(const Mesh& m, const RestrictedDual& d, std::span<const SurfacePoint> sites,
               std::vector<int32_t>& vertex_site) {
  if (d.defects.total() > 0)
    fail(ErrorCode::BadUsage, "dual mesh: the partition has " + std::to_string(d.defects.total()) +
                                  " defects; the dual would not be a manifold");
  const int32_t ns = static_cast<int32_t>(sites.size());
  if (d.cell_size.size() != sites.size()) fail(ErrorCode::BadUsage, "dual mesh: sites do not match the dual");
  Mesh out;
  std::vector<int32_t> id(ns, -1);
  vertex_site.clear();
  for (int32_t s = 0; s < ns; ++s) {
    if (d.cell_size[s] == 0) continue;
    id[s] = static_cast<int32_t>(vertex_site.size());
    vertex_site.push_back(s);
    const int32_t bv = d.boundary_vertex.empty() ? -1 : d.boundary_vertex[s];
    if (bv >= 0) {
      out.add_vertex(m.x[bv], m.y[bv], m.z[bv]);
    } else {
      const auto p = surface_point_position(m, sites[s]);
      out.add_vertex(p[0], p[1], p[2]);
    }
  }
  for (const auto& t : d.triangles) out.add_triangle(id[t[0]], id[t[1]], id[t[2]]);
  return out;
}

}  // namespace locus
