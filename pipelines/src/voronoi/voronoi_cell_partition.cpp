// Fractional partition of triangles among heat-Voronoi cells
// (pipelines/include/locus/pipelines/voronoi/voronoi_cell_partition.hpp; thesis eqs. 3.19-3.21, 3.9-3.11).
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"
#include "locus/core/host_allocator.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

namespace locus {

namespace {

// A convex polygon in barycentric coordinates (b1, b2); b0 = 1 - b1 - b2.
struct Polygon {
  std::array<std::array<double, 2>, 8> p;  // a triangle clipped twice has at most 5 corners
  int size = 0;
};

// Keeps the part where g(b) = g0 b0 + g1 b1 + g2 b2 > 0 (or == 0 when keep_zero).
Polygon clip(const Polygon& in, const double g[3], bool keep_zero) {
  Polygon out;
  auto val = [&](const std::array<double, 2>& q) { return g[0] * (1 - q[0] - q[1]) + g[1] * q[0] + g[2] * q[1]; };
  auto inside = [&](double v) { return v > 0 || (v == 0 && keep_zero); };
  for (int i = 0; i < in.size; ++i) {
    const auto& a = in.p[i];
    const auto& b = in.p[(i + 1) % in.size];
    const double ga = val(a), gb = val(b);
    if (inside(ga)) out.p[out.size++] = a;
    if (inside(ga) != inside(gb)) {
      const double s = ga / (ga - gb);  // ga != gb here
      out.p[out.size++] = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])};
    }
  }
  return out;
}

// Area fraction of the reference triangle (area 1/2) and centroid of a polygon.
void moments(const Polygon& P, double& fraction, double& c1, double& c2) {
  double a = 0, x = 0, y = 0;
  for (int i = 0; i < P.size; ++i) {
    const auto& p = P.p[i];
    const auto& q = P.p[(i + 1) % P.size];
    const double cr = p[0] * q[1] - q[0] * p[1];
    a += cr;
    x += (p[0] + q[0]) * cr;
    y += (p[1] + q[1]) * cr;
  }
  fraction = std::max(0.0, a);  // shoelace gives twice the area = the fraction of 1/2
  if (a > 0) {
    c1 = x / (3 * a);
    c2 = y / (3 * a);
  } else {
    c1 = c2 = 1.0 / 3;
  }
}

struct Entry {
  int32_t cell, vertex;
  double w;
};


// Label a's part of the triangle (see split_triangle).
void split_part(int nl, const int32_t* lab, const double (*u)[3], int a, double& fraction, double* centroid) {
  Polygon poly;
  poly.p[0] = {0, 0};
  poly.p[1] = {1, 0};
  poly.p[2] = {0, 1};
  poly.size = 3;
  for (int b = 0; b < nl && poly.size >= 3; ++b) {
    if (b == a) continue;
    const double g[3] = {u[a][0] - u[b][0], u[a][1] - u[b][1], u[a][2] - u[b][2]};
    poly = clip(poly, g, lab[a] < lab[b]);
  }
  double frac = 0, c1 = 1.0 / 3, c2 = 1.0 / 3;
  if (poly.size >= 3) moments(poly, frac, c1, c2);
  fraction = frac;
  centroid[0] = 1 - c1 - c2;
  centroid[1] = c1;
  centroid[2] = c2;
}

// Heat of site s at vertex v from the top-K lists; ok = false when it is not
// there (keep_split_rows keeps the entries the split triangles read only).
inline double top_heat(const HeatVoronoi& V, int32_t v, int32_t s, bool& ok) {
  size_t first = static_cast<size_t>(v) * kVoronoiTopK, last = first + kVoronoiTopK;
  if (!V.top_offsets.empty()) {
    first = static_cast<size_t>(V.top_offsets[v]);
    last = static_cast<size_t>(V.top_offsets[v + 1]);
  }
  for (size_t i = first; i < last; ++i)
    if (V.top_site[i] == s) return V.top_value[i];
  ok = false;
  return 0.0;
}

}  // namespace

void split_triangle(int nl, const int32_t* lab, const double (*u)[3], double* fraction, double (*centroid)[3]) {
  for (int a = 0; a < nl; ++a) split_part(nl, lab, u, a, fraction[a], centroid[a]);
}

VertexStars vertex_stars(const Mesh& m, std::span<const double> face_area) {
  return vertex_stars(m, HostVector<double>(face_area.begin(), face_area.end()));
}

namespace {

void check_star_input(const Mesh& m, size_t areas) {
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": vertex stars need a triangle mesh");
  if (areas != static_cast<size_t>(m.num_faces())) fail(ErrorCode::BadUsage, "vertex stars: one area per face expected");
}

}  // namespace

VertexStars vertex_stars(const Mesh& m, HostVector<double>&& face_area) {
  check_star_input(m, face_area.size());
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  VertexStars st;
  HostVector<int64_t>& off = st.own_offsets;
  off.assign(static_cast<size_t>(n) + 1, 0);
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) ++off[v + 1];
  }
  for (int32_t v = 0; v < n; ++v) off[v + 1] += off[v];
  st.own_faces.resize(off[n]);
  HostVector<int64_t> fill(off.begin(), off.end() - 1);
  for (int32_t f = 0; f < nf; ++f) {
    cancel_point(f);
    for (int32_t v : {m.f0[f], m.f1[f], m.f2[f]}) st.own_faces[fill[v]++] = f;
  }
  st.offsets = std::span<const int64_t>(off.data(), off.size());
  st.faces = std::span<const int32_t>(st.own_faces.data(), st.own_faces.size());
  st.area = std::move(face_area);
  st.f0 = std::span<const int32_t>(m.f0.data(), m.f0.size());
  st.f1 = std::span<const int32_t>(m.f1.data(), m.f1.size());
  st.f2 = std::span<const int32_t>(m.f2.data(), m.f2.size());
  return st;
}

VertexStars vertex_stars(const Mesh& m, std::span<const int64_t> vf_offsets, std::span<const int32_t> vf_faces,
                         HostVector<double>&& face_area) {
  check_star_input(m, face_area.size());
  if (vf_offsets.size() != static_cast<size_t>(m.num_vertices()) + 1 ||
      vf_faces.size() != 3 * static_cast<size_t>(m.num_faces()))
    fail(ErrorCode::BadUsage, "vertex stars: the face lists belong to another mesh");
  VertexStars st;
  st.offsets = vf_offsets;
  st.faces = vf_faces;
  st.area = std::move(face_area);
  st.f0 = std::span<const int32_t>(m.f0.data(), m.f0.size());
  st.f1 = std::span<const int32_t>(m.f1.data(), m.f1.size());
  st.f2 = std::span<const int32_t>(m.f2.data(), m.f2.size());
  return st;
}

namespace {

// Every triangle incident to a vertex of `cell` (labelled c), once, from its first
// corner labelled c: add(v, w) for each load w of cell c at corner v, in the
// order partition_cells produces them for that triangle.
template <class Add>
void visit_cell_loads(const VertexStars& stars, const HeatVoronoi& V, int32_t c, std::span<const int32_t> cell,
                      int64_t& fallback, Add&& add) {
  const size_t nc = cell.size();
  for (size_t i = 0; i < nc; ++i) {
    // The cell's vertices are scattered in memory: fetch ahead (offsets 8 vertices
    // ahead, the star blocks 4 ahead) so the misses overlap instead of stalling.
    if (i + 8 < nc) __builtin_prefetch(stars.offsets.data() + cell[i + 8]);
    if (i + 4 < nc) __builtin_prefetch(stars.faces.data() + stars.offsets[cell[i + 4]]);
    if (i + 2 < nc) {  // the next vertices' faces: their corners and areas
      const int32_t w = cell[i + 2];
      for (int64_t p = stars.offsets[w]; p < stars.offsets[w + 1]; ++p) {
        const int32_t f = stars.faces[p];
        __builtin_prefetch(stars.f0.data() + f);
        __builtin_prefetch(stars.f1.data() + f);
        __builtin_prefetch(stars.f2.data() + f);
        __builtin_prefetch(stars.area.data() + f);
      }
    }
    const int32_t cv = cell[i];
    for (int64_t p = stars.offsets[cv]; p < stars.offsets[cv + 1]; ++p) {
      const int32_t f = stars.faces[p];
      const int32_t v[3] = {stars.f0[f], stars.f1[f], stars.f2[f]};
      const int32_t l[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
      int first = 0;
      while (l[first] != c) ++first;  // cv is a corner labelled c
      if (v[first] != cv) continue;   // visited from its first corner labelled c
      const double A = stars.area[f];
      if (l[0] == l[1] && l[1] == l[2]) {
        for (int k = 0; k < 3; ++k) add(v[k], A / 3);
        continue;
      }
      int32_t lab[3];
      int nl = 0, mine = 0;
      for (int k = 0; k < 3; ++k)
        if (std::find(lab, lab + nl, l[k]) == lab + nl) {
          if (l[k] == c) mine = nl;
          lab[nl++] = l[k];
        }
      double u[3][3];
      bool ok = true;
      for (int a = 0; a < nl; ++a)
        for (int k = 0; k < 3; ++k) u[a][k] = top_heat(V, v[k], lab[a], ok);
      if (!ok) {  // split by vertex labels: the corners labelled c keep their third
        if (c == *std::min_element(lab, lab + nl)) ++fallback;
        for (int k = 0; k < 3; ++k)
          if (l[k] == c) add(v[k], A / 3);
        continue;
      }
      double frac = 0, cen[3];
      split_part(nl, lab, u, mine, frac, cen);
      if (frac > 0)
        for (int k = 0; k < 3; ++k)
          if (cen[k] > 0) add(v[k], A * frac * cen[k]);
    }
  }
}

}  // namespace

double accumulate_cell_load(const VertexStars& stars, const HeatVoronoi& V, int32_t c, std::span<const int32_t> cell,
                            std::span<double> acc, std::vector<int32_t>& touched, int64_t& fallback) {
  double area = 0;
  visit_cell_loads(stars, V, c, cell, fallback, [&](int32_t v, double w) {
    if (acc[v] == 0.0) touched.push_back(v);
    acc[v] += w;
    area += w;
  });
  return area;
}

double accumulate_cell_load(const VertexStars& stars, const HeatVoronoi& V, int32_t c, std::span<const int32_t> cell,
                            std::span<int32_t> slot, std::vector<double>& load, std::vector<int32_t>& touched,
                            int64_t& fallback) {
  const size_t first = touched.size();
  double area = 0;
  visit_cell_loads(stars, V, c, cell, fallback, [&](int32_t v, double w) {
    if (slot[v] < 0) {
      slot[v] = static_cast<int32_t>(load.size());
      touched.push_back(v);
      load.push_back(0.0);
    }
    load[slot[v]] += w;
    area += w;
  });
  for (size_t k = first; k < touched.size(); ++k) slot[touched[k]] = -1;
  return area;
}

HostVector<double> cell_areas(const VertexStars& stars, const HeatVoronoi& V, std::span<const int64_t> cell_offsets,
                              std::span<const int32_t> cell_vertices) {
  if (cell_offsets.empty()) fail(ErrorCode::BadUsage, "cell areas: no cells");
  if (V.top_k != kVoronoiTopK) fail(ErrorCode::BadUsage, "cell areas: the split triangles need the full top-K lists");
  const int32_t cells = static_cast<int32_t>(cell_offsets.size() - 1);
  HostVector<double> area(cells, 0.0);
  struct Load {
    int32_t vertex;
    double w;
  };
  tbb::enumerable_thread_specific<HostVector<Load>> scratch;  // a large cell's loads exceed 64 KB: the host's allocator
  tbb::parallel_for(0, cells, [&](int32_t c) {
    HostVector<Load>& loads = scratch.local();
    loads.clear();
    int64_t fallback = 0;
    const std::span<const int32_t> cell(cell_vertices.data() + cell_offsets[c],
                                        static_cast<size_t>(cell_offsets[c + 1] - cell_offsets[c]));
    visit_cell_loads(stars, V, c, cell, fallback, [&](int32_t v, double w) { loads.push_back({v, w}); });
    // partition_cells' order of the sum: by (vertex, load).
    std::sort(loads.begin(), loads.end(),
              [](const Load& a, const Load& b) { return a.vertex != b.vertex ? a.vertex < b.vertex : a.w < b.w; });
    double a = 0;
    for (const Load& l : loads) a += l.w;
    area[c] = a;
  });
  return area;
}

namespace {

// Faces in fixed chunks, processed in parallel and concatenated in chunk order
// (the result does not depend on the thread count): each face's (cell, vertex,
// load) entries, and per chunk the split and fallback counts added to P.
std::vector<HostVector<Entry>> split_faces_in_chunks(const Mesh& m, std::span<const double> face_area,
                                                     const HeatVoronoi& V, CellPartition& P) {
  const int32_t nf = m.num_faces();
  constexpr int32_t kChunk = 4096;
  const int32_t nchunks = (nf + kChunk - 1) / kChunk;
  std::vector<HostVector<Entry>> chunk_entries(nchunks);
  HostVector<int64_t> chunk_split(nchunks, 0), chunk_fallback(nchunks, 0);
  tbb::parallel_for(0, nchunks, [&](int32_t ch) {
    HostVector<Entry>& entries = chunk_entries[ch];
    entries.reserve(4 * static_cast<size_t>(kChunk));
    for (int32_t f = ch * kChunk; f < std::min(nf, (ch + 1) * kChunk); ++f) {
      const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
      const int32_t l[3] = {V.label[v[0]], V.label[v[1]], V.label[v[2]]};
      const double A = face_area[f];
      if (l[0] == l[1] && l[1] == l[2]) {
        for (int k = 0; k < 3; ++k) entries.push_back({l[0], v[k], A / 3});
        continue;
      }
      ++chunk_split[ch];
      // Distinct labels and their heat at the three corners.
      int32_t lab[3];
      int nl = 0;
      for (int k = 0; k < 3; ++k)
        if (std::find(lab, lab + nl, l[k]) == lab + nl) lab[nl++] = l[k];
      double u[3][3];
      bool ok = true;
      for (int a = 0; a < nl; ++a)
        for (int k = 0; k < 3; ++k) u[a][k] = top_heat(V, v[k], lab[a], ok);
      if (!ok) {
        ++chunk_fallback[ch];
        for (int k = 0; k < 3; ++k) entries.push_back({l[k], v[k], A / 3});
        continue;
      }
      double frac[3], cen[3][3];
      split_triangle(nl, lab, u, frac, cen);
      for (int a = 0; a < nl; ++a)
        for (int k = 0; k < 3; ++k)
          if (frac[a] > 0 && cen[a][k] > 0) entries.push_back({lab[a], v[k], A * frac[a] * cen[a][k]});
    }
  });
  for (int32_t ch = 0; ch < nchunks; ++ch) {
    P.split_faces += chunk_split[ch];
    P.fallback_faces += chunk_fallback[ch];
  }
  return chunk_entries;
}

// The entries sorted by cell (counting sort, chunk order kept), then by vertex
// within each cell with equal vertices merged: P's CSR loads and cell areas.
void merge_by_cell(const std::vector<HostVector<Entry>>& chunk_entries, int32_t cells, CellPartition& P) {
  HostVector<int64_t> start(static_cast<size_t>(cells) + 1, 0);
  for (const auto& entries : chunk_entries)
    for (const Entry& e : entries) ++start[e.cell + 1];
  for (int32_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  HostVector<Entry> sorted(start[cells]);
  {
    HostVector<int64_t> fill(start.begin(), start.end() - 1);
    for (const auto& entries : chunk_entries)
      for (const Entry& e : entries) sorted[fill[e.cell]++] = e;
  }
  // Per cell: sort by vertex (then weight) and merge in place (parallel over cells, each cell's
  // arithmetic in a fixed order), then compact.
  HostVector<int64_t> kept(cells, 0);
  P.area.assign(cells, 0.0);
  tbb::parallel_for(0, cells, [&](int32_t c) {
    auto first = sorted.begin() + start[c], last = sorted.begin() + start[c + 1];
    // (vertex, weight) is a total order up to identical entries, so the merged sums
    // do not depend on how the unstable sort permutes ties.
    std::sort(first, last, [](const Entry& a, const Entry& b) { return a.vertex != b.vertex ? a.vertex < b.vertex : a.w < b.w; });
    int64_t w = start[c];
    double area = 0;
    for (auto it = first; it != last; ++it) {
      if (w > start[c] && sorted[w - 1].vertex == it->vertex) {
        sorted[w - 1].w += it->w;
      } else {
        sorted[w++] = *it;
      }
      area += it->w;
    }
    kept[c] = w - start[c];
    P.area[c] = area;
  });
  P.offsets.assign(static_cast<size_t>(cells) + 1, 0);
  for (int32_t c = 0; c < cells; ++c) P.offsets[c + 1] = P.offsets[c] + kept[c];
  P.vertex.resize(P.offsets[cells]);
  P.load.resize(P.offsets[cells]);
  for (int32_t c = 0; c < cells; ++c)
    for (int64_t k = 0; k < kept[c]; ++k) {
      P.vertex[P.offsets[c] + k] = sorted[start[c] + k].vertex;
      P.load[P.offsets[c] + k] = sorted[start[c] + k].w;
    }
}

}  // namespace

CellPartition partition_cells(const Mesh& m, std::span<const double> face_area, const HeatVoronoi& V, int32_t cells) {
  const int32_t n = m.num_vertices(), nf = m.num_faces();
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": cell partition needs a triangle mesh");
  if (face_area.size() != static_cast<size_t>(nf))
    fail(ErrorCode::BadUsage, "cell partition: one area per face expected");
  if (V.label.size() != static_cast<size_t>(n) || V.top_k != kVoronoiTopK || !V.top_offsets.empty() ||
      V.top_site.size() != static_cast<size_t>(n) * kVoronoiTopK)
    fail(ErrorCode::BadUsage, "cell partition: labels and heat lists of another mesh");
  if (cells < 1) fail(ErrorCode::BadUsage, "cell partition: no cells");
  for (int32_t v = 0; v < n; ++v)
    if (V.label[v] < 0 || V.label[v] >= cells)
      fail(ErrorCode::BadUsage, "cell partition: vertex " + std::to_string(v) + " has label " +
                                    std::to_string(V.label[v]) + ", outside 0.." + std::to_string(cells - 1));
  CellPartition P;
  const std::vector<HostVector<Entry>> entries = split_faces_in_chunks(m, face_area, V, P);
  merge_by_cell(entries, cells, P);
  return P;
}

}  // namespace locus
