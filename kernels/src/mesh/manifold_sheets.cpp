// The manifold sheets of a triangle soup (manifold_sheets.hpp): the surface a
// CVT remesh (thesis §3.7) can be built on when an asset is not a manifold.
// Faces are cleaned first (T-junctions closed by flat triangles are split,
// other degenerate and repeated faces dropped), then glued in pairs along
// their edges, oriented by a breadth-first walk, and every vertex split into
// one copy per fan of glued faces (a union-find over corners). A last check
// drops a face wherever two faces would still share an edge they are not
// glued along (possible only where a cut edge ends inside a fan), and the
// gluing is redone without it.
#include "locus/kernels/mesh/manifold_sheets.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {
namespace {

using Tri = std::array<int32_t, 3>;

struct Faces {
  std::vector<Tri> tri;
  std::vector<int32_t> src;
  std::vector<std::array<double, 9>> bary;  // per corner k: bary[3k..3k+2] in the input face
};

struct Vec {
  double x, y, z;
};
Vec pos(const Mesh& m, int32_t v) { return {m.x[v], m.y[v], m.z[v]}; }
Vec sub(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// Twice the area of triangle t, times sc^2 (power_of_two_scale, as analyze_mesh).
double scaled_area(const Mesh& m, const Tri& t, double sc) {
  const Vec o = pos(m, t[0]);
  const Vec u = sub(pos(m, t[1]), o), w = sub(pos(m, t[2]), o);
  const Vec c = cross({u.x * sc, u.y * sc, u.z * sc}, {w.x * sc, w.y * sc, w.z * sc});
  return 0.5 * std::sqrt(dot(c, c));
}

uint64_t edge_key(int32_t a, int32_t b) {
  const uint32_t lo = static_cast<uint32_t>(std::min(a, b)), hi = static_cast<uint32_t>(std::max(a, b));
  return (static_cast<uint64_t>(lo) << 32) | hi;
}

std::array<double, 9> identity_bary() { return {1, 0, 0, 0, 1, 0, 0, 0, 1}; }

// Splits face g at vertex w on its edge {u, v}: g's run p -> q becomes p -> w -> q.
// Returns false (nothing changed) when a half would have no area.
bool split_at(const Mesh& m, Faces& F, int32_t g, int32_t u, int32_t v, int32_t w, double sc, double threshold) {
  const Tri G = F.tri[g];
  int k = 0;
  while (k < 3 && !((G[k] == u && G[(k + 1) % 3] == v) || (G[k] == v && G[(k + 1) % 3] == u))) ++k;
  if (k == 3) return false;
  const int32_t p = G[k], q = G[(k + 1) % 3], x = G[(k + 2) % 3];
  const Tri a = {p, w, x}, b = {w, q, x};
  if (!(scaled_area(m, a, sc) > threshold) || !(scaled_area(m, b, sc) > threshold)) return false;
  const Vec pq = sub(pos(m, q), pos(m, p));
  const double t = std::clamp(dot(sub(pos(m, w), pos(m, p)), pq) / dot(pq, pq), 0.0, 1.0);
  const std::array<double, 9> B = F.bary[g];
  const int kp = k, kq = (k + 1) % 3, kx = (k + 2) % 3;
  std::array<double, 3> bw;
  for (int j = 0; j < 3; ++j) bw[j] = (1 - t) * B[3 * kp + j] + t * B[3 * kq + j];
  auto row = [&](int c) { return std::array<double, 3>{B[3 * c], B[3 * c + 1], B[3 * c + 2]}; };
  auto pack = [](std::array<double, 3> r0, std::array<double, 3> r1, std::array<double, 3> r2) {
    return std::array<double, 9>{r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2]};
  };
  F.tri[g] = a;
  F.bary[g] = pack(row(kp), bw, row(kx));
  F.tri.push_back(b);
  F.src.push_back(F.src[g]);
  F.bary.push_back(pack(bw, row(kq), row(kx)));
  return true;
}

// The input's faces without repeated vertices or repeated faces; flat faces
// closing a T-junction replaced by the split of the face across their longest edge.
Faces clean_faces(const Mesh& m, ManifoldSheets& out) {
  const double h = mean_edge_length(m);
  const double sc = power_of_two_scale(h), hs = h * sc;
  const double threshold = kDegenerateAreaRelative * hs * hs;
  Faces F;
  std::vector<std::tuple<int32_t, int32_t, int32_t, int32_t>> sorted;  // sorted ids, face
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    Tri t = {m.f0[f], m.f1[f], m.f2[f]};
    Tri s = t;
    std::sort(s.begin(), s.end());
    if (s[0] == s[1] || s[1] == s[2]) {
      ++out.dropped_faces;
      continue;
    }
    sorted.emplace_back(s[0], s[1], s[2], f);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<char> keep(static_cast<size_t>(m.num_faces()), 0);
  for (size_t i = 0; i < sorted.size(); ++i) {
    const bool repeat = i > 0 && std::get<0>(sorted[i]) == std::get<0>(sorted[i - 1]) &&
                        std::get<1>(sorted[i]) == std::get<1>(sorted[i - 1]) &&
                        std::get<2>(sorted[i]) == std::get<2>(sorted[i - 1]);
    if (repeat) ++out.dropped_faces;
    else keep[std::get<3>(sorted[i])] = 1;
  }
  std::vector<int32_t> flat;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    if (!keep[f]) continue;
    const Tri t = {m.f0[f], m.f1[f], m.f2[f]};
    if (!(scaled_area(m, t, sc) > threshold)) {
      flat.push_back(f);
      continue;
    }
    F.tri.push_back(t);
    F.src.push_back(f);
    F.bary.push_back(identity_bary());
  }
  if (flat.empty()) return F;
  // Faces per edge of the kept faces, for the T-junctions.
  std::vector<std::pair<uint64_t, int32_t>> by_edge;
  for (int32_t g = 0; g < static_cast<int32_t>(F.tri.size()); ++g)
    for (int k = 0; k < 3; ++k) by_edge.emplace_back(edge_key(F.tri[g][k], F.tri[g][(k + 1) % 3]), g);
  std::sort(by_edge.begin(), by_edge.end());
  std::vector<char> split(F.tri.size(), 0);
  for (const int32_t f : flat) {
    const Tri t = {m.f0[f], m.f1[f], m.f2[f]};
    int longest = 0;  // the edge t[k] -> t[k+1] of greatest length
    double best = -1;
    for (int k = 0; k < 3; ++k) {
      const Vec e = sub(pos(m, t[(k + 1) % 3]), pos(m, t[k]));
      if (dot(e, e) > best) best = dot(e, e), longest = k;
    }
    const int32_t u = t[longest], v = t[(longest + 1) % 3], w = t[(longest + 2) % 3];
    const uint64_t key = edge_key(u, v);
    auto lo = std::lower_bound(by_edge.begin(), by_edge.end(), std::make_pair(key, INT32_MIN));
    auto hi = std::upper_bound(by_edge.begin(), by_edge.end(), std::make_pair(key, INT32_MAX));
    bool done = false;
    if (hi - lo == 1 && !split[lo->second]) {
      done = split_at(m, F, lo->second, u, v, w, sc, threshold);
      if (done) split[lo->second] = 1;
    }
    if (done) ++out.split_faces;
    else ++out.dropped_faces;
  }
  return F;
}

// Per corner edge 3f + k (the run tri[f][k] -> tri[f][k+1]): the glued corner edge, or -1.
std::vector<int32_t> glue_edges(const Mesh& m, const Faces& F, int64_t& cut_edges) {
  const int32_t nf = static_cast<int32_t>(F.tri.size());
  std::vector<std::pair<uint64_t, int32_t>> half(static_cast<size_t>(3) * nf);
  for (int32_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) half[3 * f + k] = {edge_key(F.tri[f][k], F.tri[f][(k + 1) % 3]), 3 * f + k};
  std::sort(half.begin(), half.end());
  std::vector<int32_t> partner(half.size(), -1);
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    while (j < half.size() && half[j].first == half[i].first) ++j;
    if (j - i == 2) {
      partner[half[i].second] = half[i + 1].second, partner[half[i + 1].second] = half[i].second;
    } else if (j - i > 2) {
      ++cut_edges;
      // Each face's direction in its plane away from the edge; the most opposite pairs glue first.
      std::vector<Vec> dir;
      for (size_t q = i; q < j; ++q) {
        const int32_t c = half[q].second, f = c / 3, k = c % 3;
        const Vec a = pos(m, F.tri[f][k]), e = sub(pos(m, F.tri[f][(k + 1) % 3]), a);
        const Vec o = sub(pos(m, F.tri[f][(k + 2) % 3]), a);
        const double s = dot(o, e) / dot(e, e);
        Vec d = {o.x - s * e.x, o.y - s * e.y, o.z - s * e.z};
        const double len = std::sqrt(dot(d, d));
        dir.push_back(len > 0 ? Vec{d.x / len, d.y / len, d.z / len} : Vec{0, 0, 0});
      }
      std::vector<std::tuple<double, size_t, size_t>> pairs;
      for (size_t a = 0; a < dir.size(); ++a)
        for (size_t b = a + 1; b < dir.size(); ++b) pairs.emplace_back(dot(dir[a], dir[b]), a, b);
      std::sort(pairs.begin(), pairs.end());
      for (const auto& [d, a, b] : pairs) {
        const int32_t ca = half[i + a].second, cb = half[i + b].second;
        if (partner[ca] < 0 && partner[cb] < 0) partner[ca] = cb, partner[cb] = ca;
      }
    }
    i = j;
  }
  return partner;
}

// Orients the faces per sheet (flip[f] = 1 reverses face f) and cuts the glued
// edges the orientation contradicts.
std::vector<char> orient(const Faces& F, std::vector<int32_t>& partner, int64_t& cut_edges, int64_t& flipped) {
  const int32_t nf = static_cast<int32_t>(F.tri.size());
  std::vector<char> flip(nf, 0), seen(nf, 0);
  auto same_direction = [&](int32_t c, int32_t d) { return F.tri[c / 3][c % 3] == F.tri[d / 3][d % 3]; };
  std::vector<int32_t> queue, sheet;
  for (int32_t root = 0; root < nf; ++root) {
    if (seen[root]) continue;
    queue.assign(1, root);
    seen[root] = 1;
    sheet.clear();
    for (size_t q = 0; q < queue.size(); ++q) {
      const int32_t f = queue[q];
      sheet.push_back(f);
      for (int k = 0; k < 3; ++k) {
        const int32_t d = partner[3 * f + k];
        if (d < 0 || seen[d / 3]) continue;
        seen[d / 3] = 1;
        flip[d / 3] = static_cast<char>(flip[f] ^ (same_direction(3 * f + k, d) ? 1 : 0));
        queue.push_back(d / 3);
      }
    }
    int64_t n = 0;
    for (const int32_t f : sheet) n += flip[f];
    if (2 * n > static_cast<int64_t>(sheet.size()))  // keep the orientation most faces have
      for (const int32_t f : sheet) flip[f] ^= 1;
  }
  for (int32_t c = 0; c < 3 * nf; ++c) {
    const int32_t d = partner[c];
    if (d < c) continue;
    if ((flip[c / 3] ^ flip[d / 3]) != (same_direction(c, d) ? 1 : 0)) {
      partner[c] = partner[d] = -1;
      ++cut_edges;
    }
  }
  flipped = std::count(flip.begin(), flip.end(), 1);
  return flip;
}

int32_t find(std::vector<int32_t>& parent, int32_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

// Sheet vertex per corner: corners glued around the same input vertex share one.
std::vector<int32_t> corner_vertices(const Faces& F, const std::vector<int32_t>& partner,
                                     std::vector<int32_t>& vertex_of) {
  const int32_t nc = static_cast<int32_t>(3 * F.tri.size());
  std::vector<int32_t> parent(nc);
  std::iota(parent.begin(), parent.end(), 0);
  auto unite = [&](int32_t a, int32_t b) {
    a = find(parent, a), b = find(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  auto next = [](int32_t c) { return c - c % 3 + (c % 3 + 1) % 3; };
  auto vert = [&](int32_t c) { return F.tri[c / 3][c % 3]; };
  for (int32_t c = 0; c < nc; ++c) {
    const int32_t d = partner[c];
    if (d < c) continue;
    if (vert(c) == vert(d)) unite(c, d), unite(next(c), next(d));
    else unite(c, next(d)), unite(next(c), d);
  }
  // Sheet vertices numbered by input vertex, then by first corner.
  std::vector<int32_t> order(nc);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return vert(a) < vert(b); });
  std::vector<int32_t> id(nc, -1), out(nc);
  vertex_of.clear();
  for (const int32_t c : order) {
    const int32_t r = find(parent, c);
    if (id[r] < 0) id[r] = static_cast<int32_t>(vertex_of.size()), vertex_of.push_back(vert(c));
    out[c] = id[r];
  }
  return out;
}

// Faces that share a sheet edge they are not glued along (a cut that ends inside a fan):
// all but the first on each such edge.
std::vector<int32_t> conflicting_faces(const std::vector<int32_t>& cv, const std::vector<int32_t>& partner) {
  const int32_t nf = static_cast<int32_t>(cv.size() / 3);
  std::vector<std::pair<uint64_t, int32_t>> half;
  for (int32_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) half.emplace_back(edge_key(cv[3 * f + k], cv[3 * f + (k + 1) % 3]), 3 * f + k);
  std::sort(half.begin(), half.end());
  std::vector<int32_t> bad;
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    while (j < half.size() && half[j].first == half[i].first) ++j;
    const bool glued = j - i == 2 && partner[half[i].second] == half[i + 1].second;
    if (j - i > 1 && !glued)
      for (size_t q = i + 1; q < j; ++q) bad.push_back(half[q].second / 3);
    i = j;
  }
  std::sort(bad.begin(), bad.end());
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  return bad;
}

}  // namespace

ManifoldSheets manifold_sheets(const Mesh& m) {
  validate_mesh_arrays(m);
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": manifold sheets need a triangle mesh");
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v]))
      fail(ErrorCode::BadInput, mesh_name(m) + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  ManifoldSheets out;
  Faces F = clean_faces(m, out);
  std::vector<int32_t> partner, cv;
  std::vector<char> flip;
  for (;;) {
    int64_t cut = 0, flipped = 0;
    partner = glue_edges(m, F, cut);
    flip = orient(F, partner, cut, flipped);
    std::vector<int32_t> vertex_of;
    cv = corner_vertices(F, partner, vertex_of);
    const std::vector<int32_t> bad = conflicting_faces(cv, partner);
    if (bad.empty()) {
      out.cut_edges = cut, out.flipped_faces = flipped;
      out.vertex_of.assign(vertex_of.begin(), vertex_of.end());
      break;
    }
    out.dropped_faces += static_cast<int64_t>(bad.size());
    Faces kept;
    size_t b = 0;
    for (int32_t f = 0; f < static_cast<int32_t>(F.tri.size()); ++f) {
      if (b < bad.size() && bad[b] == f) {
        ++b;
        continue;
      }
      kept.tri.push_back(F.tri[f]), kept.src.push_back(F.src[f]), kept.bary.push_back(F.bary[f]);
    }
    F = std::move(kept);
  }
  std::vector<char> referenced(static_cast<size_t>(m.num_vertices()), 0);
  for (const int32_t v : out.vertex_of) referenced[v] = 1;
  out.unreferenced_vertices = std::count(referenced.begin(), referenced.end(), 0);
  out.split_vertices = static_cast<int64_t>(out.vertex_of.size()) - (m.num_vertices() - out.unreferenced_vertices);
  Mesh& s = out.mesh;
  s.source = m.source;
  for (const int32_t v : out.vertex_of) s.add_vertex(m.x[v], m.y[v], m.z[v]);
  for (size_t f = 0; f < F.tri.size(); ++f) {
    std::array<int32_t, 3> t = {cv[3 * f], cv[3 * f + 1], cv[3 * f + 2]};
    std::array<double, 9> B = F.bary[f];
    if (flip[f]) {
      std::swap(t[1], t[2]);
      for (int j = 0; j < 3; ++j) std::swap(B[3 + j], B[6 + j]);
    }
    s.add_triangle(t[0], t[1], t[2]);
    out.face_of.push_back(F.src[f]);
    out.corner_bary.push_back(B);
  }
  return out;
}

}  // namespace locus
