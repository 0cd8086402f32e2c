// Feature graph of a remesh's input and the sites that keep its creases
// (pipelines/include/locus/pipelines/voronoi/remesh_features.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_features.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <string>
#include <unordered_map>

#include "locus/error.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

using namespace remesh_vec3;

V3 face_normal(const Mesh& m, int32_t f) { return tri_normal(pos(m, m.f0[f]), pos(m, m.f1[f]), pos(m, m.f2[f])); }

// Per edge: 1 when it is a feature edge (two faces, normals more than
// angle_deg apart; a zero-area face has no normal and makes none).
std::vector<uint8_t> feature_edges(const Mesh& m, const EdgeIncidence& inc, double angle_deg) {
  const size_t ne = inc.edges.e0.size();
  std::vector<uint8_t> sharp(ne, 0);
  const double cos_max = std::cos(angle_deg * M_PI / 180);
  const EdgeCorners corners(inc);
  for (size_t e = 0; e < ne; ++e) {
    if (inc.edges.face_count[e] != 2) continue;
    const int64_t c0 = corners.offsets()[e];
    const V3 na = face_normal(m, corners.corners()[c0] / 3), nb = face_normal(m, corners.corners()[c0 + 1] / 3);
    const double la = norm(na), lb = norm(nb);
    if (la > 0 && lb > 0 && dot(na, nb) < cos_max * la * lb) sharp[e] = 1;
  }
  return sharp;
}

// The edge id of u-w (u != w), -1 when none.
int32_t edge_of(const EdgeIncidence& inc, int32_t u, int32_t w) {
  const int32_t a = std::min(u, w), b = std::max(u, w);
  // Edges are sorted by (e0, e1): binary search.
  const auto& e0 = inc.edges.e0;
  const auto& e1 = inc.edges.e1;
  size_t lo = 0, hi = e0.size();
  while (lo < hi) {
    const size_t mid = (lo + hi) / 2;
    if (e0[mid] < a || (e0[mid] == a && e1[mid] < b)) lo = mid + 1;
    else hi = mid;
  }
  return lo < e0.size() && e0[lo] == a && e1[lo] == b ? static_cast<int32_t>(lo) : -1;
}

// The point at fraction t of edge u-w as a point of one of its faces.
SurfacePoint edge_point(const Mesh& m, const EdgeIncidence& inc, const EdgeCorners& corners, int32_t u, int32_t w,
                        double t) {
  if (t <= 1e-9) return vertex_point(u);
  if (t >= 1 - 1e-9) return vertex_point(w);
  const int32_t e = edge_of(inc, u, w);
  const int32_t f = corners.first(e) / 3;
  SurfacePoint p;
  p.face = f;
  p.bary = {0, 0, 0};
  const int32_t fv[3] = {m.f0[f], m.f1[f], m.f2[f]};
  for (int k = 0; k < 3; ++k) {
    if (fv[k] == u) p.bary[k] = 1 - t;
    if (fv[k] == w) p.bary[k] = t;
  }
  return p;
}

// The largest distance from the vertices of polyline c (arclengths s) to the
// chords of its `steps` equal arclength steps.
double chord_error(const Mesh& m, const std::vector<int32_t>& c, const std::vector<double>& s, int64_t steps) {
  const double len = s.back();
  auto at = [&](double a, size_t& i) {
    while (i + 2 < s.size() && s[i + 1] < a) ++i;
    const double seg = s[i + 1] - s[i], t = seg > 0 ? (a - s[i]) / seg : 0.0;
    const V3 p = pos(m, c[i]), q = pos(m, c[i + 1]);
    return V3{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
  };
  double worst = 0;
  size_t i = 0, j = 1;
  V3 a = pos(m, c[0]);
  for (int64_t k = 1; k <= steps; ++k) {
    const double sb = len * static_cast<double>(k) / static_cast<double>(steps);
    const V3 b = at(sb, i), d = sub(b, a);
    const double dd = dot(d, d);
    for (; j + 1 < c.size() && s[j] < sb; ++j) {
      const V3 w = sub(pos(m, c[j]), a);
      const double t = dd > 0 ? std::clamp(dot(w, d) / dd, 0.0, 1.0) : 0.0;
      worst = std::max(worst, norm(V3{w[0] - t * d[0], w[1] - t * d[1], w[2] - t * d[2]}));
    }
    a = b;
  }
  return worst;
}

// Greedy thinning in the given order: a point closer than `sep` to one kept
// before goes (a hash grid of cells `sep` wide). Clusters of corners and short
// curves (a CAD tessellation's needles) get no more sites than the density
// has room for; a sample landing on a corner repeats it and goes too.
std::vector<int32_t> thinned(const Mesh& m, const std::vector<SurfacePoint>& pts, double sep) {
  std::unordered_map<uint64_t, std::vector<V3>> grid;
  auto cell = [&](double x) { return static_cast<int64_t>(std::floor(x / sep)); };
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return (static_cast<uint64_t>(i & 0x1fffff) << 42) | (static_cast<uint64_t>(j & 0x1fffff) << 21) |
           static_cast<uint64_t>(k & 0x1fffff);
  };
  std::vector<int32_t> out;
  for (size_t i = 0; i < pts.size(); ++i) {
    const V3 p = surface_point_position(m, pts[i]);
    const int64_t ci = cell(p[0]), cj = cell(p[1]), ck = cell(p[2]);
    bool near = false;
    for (int64_t i = ci - 1; i <= ci + 1 && !near; ++i)
      for (int64_t j = cj - 1; j <= cj + 1 && !near; ++j)
        for (int64_t k = ck - 1; k <= ck + 1 && !near; ++k) {
          const auto it = grid.find(key(i, j, k));
          if (it == grid.end()) continue;
          for (const V3& q : it->second) near = near || norm(sub(p, q)) < sep;
        }
    if (near) continue;
    grid[key(ci, cj, ck)].push_back(p);
    out.push_back(static_cast<int32_t>(i));
  }
  return out;
}

}  // namespace

double feature_spacing(double area, int32_t sites) {
  return std::sqrt(2 * area / (std::sqrt(3.0) * std::max(1, sites)));
}

FeatureGraph feature_graph(const Mesh& m, const MeshDerived& d, double angle_deg) {
  if (!(angle_deg > 0 && angle_deg < 180))
    fail(ErrorCode::BadUsage, "features: the dihedral angle must be in (0, 180) degrees, got " +
                                  std::to_string(angle_deg));
  const EdgeIncidence& inc = d.incidence;
  const std::vector<uint8_t> sharp = feature_edges(m, inc, angle_deg);
  const int32_t n = m.num_vertices();
  FeatureGraph g;
  // Per vertex its feature edges (CSR over the sharp ones).
  std::vector<int32_t> deg(n, 0), nb_off(static_cast<size_t>(n) + 1, 0);
  std::vector<uint8_t> on_boundary(n, 0);
  for (size_t e = 0; e < sharp.size(); ++e) {
    if (inc.edges.face_count[e] == 1) on_boundary[inc.edges.e0[e]] = on_boundary[inc.edges.e1[e]] = 1;
    if (!sharp[e]) continue;
    ++g.edges;
    ++deg[inc.edges.e0[e]], ++deg[inc.edges.e1[e]];
  }
  for (int32_t v = 0; v < n; ++v) nb_off[v + 1] = nb_off[v] + deg[v];
  std::vector<int32_t> nb_edge(static_cast<size_t>(nb_off[n]));
  std::vector<int32_t> fill(nb_off.begin(), nb_off.end() - 1);
  for (size_t e = 0; e < sharp.size(); ++e)
    if (sharp[e]) {
      nb_edge[fill[inc.edges.e0[e]]++] = static_cast<int32_t>(e);
      nb_edge[fill[inc.edges.e1[e]]++] = static_cast<int32_t>(e);
    }
  auto other = [&](int32_t e, int32_t v) { return inc.edges.e0[e] == v ? inc.edges.e1[e] : inc.edges.e0[e]; };
  std::vector<uint8_t> corner(n, 0);
  for (int32_t v = 0; v < n; ++v) {
    if (deg[v] == 0) continue;
    bool c = deg[v] != 2 || on_boundary[v];
    if (!c) {  // a curve turning more than 45 degrees
      const V3 a = pos(m, other(nb_edge[nb_off[v]], v)), p = pos(m, v), b = pos(m, other(nb_edge[nb_off[v] + 1], v));
      const V3 u = sub(p, a), w = sub(b, p);
      c = norm(u) > 0 && norm(w) > 0 && dot(u, w) < std::sqrt(0.5) * norm(u) * norm(w);
    }
    if (c) {
      corner[v] = 1;
      g.corners.push_back(v);
    }
  }
  std::vector<uint8_t> used(sharp.size(), 0);
  auto walk = [&](int32_t start, int32_t e) {  // from `start` along e until a corner or back at start
    std::vector<int32_t> chain{start};
    int32_t v = start;
    while (true) {
      used[e] = 1;
      v = other(e, v);
      chain.push_back(v);
      if (corner[v] || v == start) break;
      int32_t next = -1;
      for (int64_t k = nb_off[v]; k < nb_off[v + 1]; ++k)
        if (!used[nb_edge[k]]) next = nb_edge[k];
      if (next < 0) break;
      e = next;
    }
    g.curves.push_back(std::move(chain));
  };
  for (int32_t v : g.corners)
    for (int64_t k = nb_off[v]; k < nb_off[v + 1]; ++k)
      if (!used[nb_edge[k]]) walk(v, nb_edge[k]);
  for (int32_t v = 0; v < n; ++v)  // closed loops without a corner
    for (int64_t k = nb_off[v]; k < nb_off[v + 1]; ++k)
      if (!used[nb_edge[k]]) walk(v, nb_edge[k]);
  return g;
}

std::vector<std::pair<int32_t, int32_t>> feature_curve_edges(const std::vector<FeatureCurve>& curves) {
  std::vector<std::pair<int32_t, int32_t>> out;
  auto add = [&](int32_t a, int32_t b) { out.push_back({std::min(a, b), std::max(a, b)}); };
  for (const FeatureCurve& c : curves) {
    for (size_t k = 1; k < c.site.size(); ++k) add(c.site[k - 1], c.site[k]);
    if (c.closed && c.site.size() > 2) add(c.site.back(), c.site.front());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void drop_short_components(const Mesh& m, FeatureGraph& g, double min_length) {
  // Union-find over the curves: two curves are connected when they share an end.
  const size_t nc = g.curves.size();
  std::vector<size_t> parent(nc);
  for (size_t i = 0; i < nc; ++i) parent[i] = i;
  std::function<size_t(size_t)> root = [&](size_t i) { return parent[i] == i ? i : parent[i] = root(parent[i]); };
  std::unordered_map<int32_t, size_t> at_end;
  for (size_t i = 0; i < nc; ++i)
    for (int32_t v : {g.curves[i].front(), g.curves[i].back()}) {
      const auto [it, fresh] = at_end.try_emplace(v, i);
      if (!fresh) parent[root(i)] = root(it->second);
    }
  std::vector<double> length(nc, 0.0);
  for (size_t i = 0; i < nc; ++i) {
    const std::vector<int32_t>& c = g.curves[i];
    for (size_t k = 1; k < c.size(); ++k) length[root(i)] += norm(sub(pos(m, c[k]), pos(m, c[k - 1])));
  }
  FeatureGraph kept;
  std::vector<uint8_t> end(static_cast<size_t>(m.num_vertices()), 0);
  for (size_t i = 0; i < nc; ++i) {
    if (length[root(i)] < min_length) continue;
    kept.edges += static_cast<int64_t>(g.curves[i].size()) - 1;
    end[g.curves[i].front()] = end[g.curves[i].back()] = 1;
    kept.curves.push_back(std::move(g.curves[i]));
  }
  for (int32_t v : g.corners)
    if (end[v]) kept.corners.push_back(v);
  g = std::move(kept);
}

std::vector<SurfacePoint> feature_sites(const Mesh& m, const MeshDerived& d, const FeatureGraph& g, double spacing,
                                        std::vector<FeatureCurve>* curves) {
  std::vector<SurfacePoint> out;
  std::vector<std::pair<int32_t, double>> on;  // per point: its curve (-1: a corner) and arclength
  // Corners where most curves end first (they keep their place in thinned).
  std::vector<int32_t> ends(static_cast<size_t>(m.num_vertices()), 0);
  for (const std::vector<int32_t>& c : g.curves)
    if (c.front() != c.back()) ++ends[c.front()], ++ends[c.back()];
  std::vector<int32_t> corners = g.corners;
  std::stable_sort(corners.begin(), corners.end(), [&](int32_t a, int32_t b) { return ends[a] > ends[b]; });
  for (int32_t v : corners) out.push_back(vertex_point(v)), on.push_back({-1, 0.0});
  const EdgeCorners edge_corners(d.incidence);
  for (size_t ci = 0; ci < g.curves.size(); ++ci) {
    const std::vector<int32_t>& c = g.curves[ci];
    std::vector<double> s{0};
    for (size_t i = 1; i < c.size(); ++i) s.push_back(s.back() + norm(sub(pos(m, c[i]), pos(m, c[i - 1]))));
    const double len = s.back();
    const bool closed = c.front() == c.back();
    int64_t steps = std::max<int64_t>(closed ? 3 : 1, std::llround(len / spacing));
    // A bent curve gets more steps (at most twice as many), until its chords
    // are within a tenth of the spacing of it.
    for (const int64_t most = 2 * steps; steps < most && chord_error(m, c, s, steps) > 0.1 * spacing;) ++steps;
    if (closed) out.push_back(vertex_point(c.front())), on.push_back({static_cast<int32_t>(ci), 0.0});
    size_t i = 0;
    for (int64_t k = 1; k < steps; ++k) {
      const double at = len * static_cast<double>(k) / static_cast<double>(steps);
      while (i + 2 < s.size() && s[i + 1] < at) ++i;
      const double seg = s[i + 1] - s[i];
      out.push_back(edge_point(m, d.incidence, edge_corners, c[i], c[i + 1], seg > 0 ? (at - s[i]) / seg : 0.0));
      on.push_back({static_cast<int32_t>(ci), at});
    }
  }
  const std::vector<int32_t> keep = thinned(m, out, 0.4 * spacing);
  std::vector<SurfacePoint> kept;
  for (int32_t i : keep) kept.push_back(out[i]);
  if (!curves) return kept;
  // The curves with their kept sites in order (an open curve's corners at its ends).
  std::unordered_map<int32_t, int32_t> corner_site;
  curves->assign(g.curves.size(), FeatureCurve{});
  for (size_t ci = 0; ci < g.curves.size(); ++ci) {
    const std::vector<int32_t>& c = g.curves[ci];
    FeatureCurve& fc = (*curves)[ci];
    // A loop through a corner is an open curve from the corner back to it.
    fc.closed = c.front() == c.back() && !std::binary_search(g.corners.begin(), g.corners.end(), c.front());
    for (size_t k = 0; k + (fc.closed ? 1 : 0) < c.size(); ++k) fc.p.push_back(pos(m, c[k]));
  }
  for (size_t k = 0; k < keep.size(); ++k) {
    const auto [ci, at] = on[keep[k]];
    if (ci < 0) corner_site[out[keep[k]].vertex] = static_cast<int32_t>(k);
    else (*curves)[ci].site.push_back(static_cast<int32_t>(k)), (*curves)[ci].s.push_back(at);
  }
  for (size_t ci = 0; ci < g.curves.size(); ++ci) {
    FeatureCurve& fc = (*curves)[ci];
    if (fc.closed) continue;
    const auto a = corner_site.find(g.curves[ci].front()), b = corner_site.find(g.curves[ci].back());
    double len = 0;
    for (size_t k = 1; k < fc.p.size(); ++k) len += norm(sub(fc.p[k], fc.p[k - 1]));
    if (a != corner_site.end()) fc.site.insert(fc.site.begin(), a->second), fc.s.insert(fc.s.begin(), 0.0);
    if (b != corner_site.end()) fc.site.push_back(b->second), fc.s.push_back(len);
  }
  return kept;
}

std::vector<SurfacePoint> split_largest_cells(const Mesh& m, const MeshDerived& d, std::span<const int32_t> label,
                                              std::vector<SurfacePoint> sites, int32_t count, int32_t fixed) {
  const int32_t ns = static_cast<int32_t>(sites.size()), n = m.num_vertices();
  std::vector<double> area(ns, 0.0);
  for (int32_t v = 0; v < n; ++v) area[label[v]] += d.mass[v];
  std::vector<int32_t> order;
  for (int32_t s = fixed; s < ns; ++s) order.push_back(s);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return area[a] > area[b]; });
  order.resize(std::min<size_t>(order.size(), static_cast<size_t>(std::max(0, count))));
  std::vector<int32_t> rank(ns, -1), far(order.size(), -1);
  std::vector<double> far_d(order.size(), -1.0);
  for (size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<int32_t>(k);
  for (int32_t v = 0; v < n; ++v) {
    const int32_t k = rank[label[v]];
    if (k < 0) continue;
    const V3 p = surface_point_position(m, sites[label[v]]), q = pos(m, v);
    const double dd = dot(sub(p, q), sub(p, q));
    if (dd > far_d[k]) far_d[k] = dd, far[k] = v;
  }
  for (int32_t v : far)
    if (v >= 0) sites.push_back(vertex_point(v));
  return sites;
}

std::vector<double> feature_distance(const Mesh& m, const MeshDerived& d, const FeatureGraph& g) {
  const int32_t n = m.num_vertices();
  std::vector<double> dist(n, INFINITY);
  using Item = std::pair<double, int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  for (const std::vector<int32_t>& c : g.curves)
    for (int32_t v : c)
      if (dist[v] > 0) dist[v] = 0, heap.push({0.0, v});
  for (int32_t v : g.corners)
    if (dist[v] > 0) dist[v] = 0, heap.push({0.0, v});
  const Adjacency& adj = d.adjacency;
  while (!heap.empty()) {
    const auto [dv, v] = heap.top();
    heap.pop();
    if (dv > dist[v]) continue;
    for (int64_t k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
      const int32_t w = adj.neighbors[k];
      const double dw = dv + norm(sub(pos(m, v), pos(m, w)));
      if (dw < dist[w]) dist[w] = dw, heap.push({dw, w});
    }
  }
  return dist;
}

std::vector<FeatureCurve> feature_slides(const std::vector<FeatureCurve>& lines, std::span<const int32_t> vertex_site,
                                         int32_t feature_sites) {
  std::vector<int32_t> vertex(static_cast<size_t>(std::max(0, feature_sites)), -1);
  for (size_t i = 0; i < vertex_site.size(); ++i)
    if (vertex_site[i] >= 0 && vertex_site[i] < feature_sites) vertex[vertex_site[i]] = static_cast<int32_t>(i);
  std::vector<FeatureCurve> out;
  for (const FeatureCurve& c : lines) {
    FeatureCurve s{c.p, c.closed, {}, {}};
    for (size_t k = 0; k < c.site.size(); ++k)
      if (vertex[c.site[k]] >= 0) s.site.push_back(vertex[c.site[k]]), s.s.push_back(c.s[k]);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<SurfacePoint> with_feature_sites(const Mesh& m, const MeshDerived& d, const FeatureGraph& g,
                                             std::span<const SurfacePoint> sites, double spacing, double band,
                                             int32_t& feature_count, std::vector<FeatureCurve>* curves) {
  std::vector<SurfacePoint> out = feature_sites(m, d, g, spacing, curves);
  feature_count = static_cast<int32_t>(out.size());
  const std::vector<double> dist = feature_distance(m, d, g);
  for (const SurfacePoint& s : sites) {
    int32_t v[3];
    double w[3];
    const int k = surface_point_support(m, s, v, w);
    const V3 p = surface_point_position(m, s);
    double near = INFINITY;
    for (int i = 0; i < k; ++i) near = std::min(near, dist[v[i]] + norm(sub(p, pos(m, v[i]))));
    if (near > band * spacing) out.push_back(s);
  }
  return out;
}

}  // namespace locus
