// Tests for pipelines/voronoi_cell_partition (split triangles, cell loads).
// Oracle: heat values that are linear functions of position are interpolated
// exactly on every triangle, so the split lines are the exact lines where the
// functions are equal and the cell areas and first moments are known in closed form.
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"

#include <doctest/doctest.h>

#include <algorithm>

#include <cmath>
#include <functional>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/error.hpp"

using namespace locus;

namespace {

// Labels and top-K lists of `cells` linear "heat" functions f[c](x, y).
HeatVoronoi linear_heat(const Mesh& m, const std::vector<std::function<double(double, double)>>& f) {
  const int32_t n = m.num_vertices();
  HeatVoronoi V;
  V.label.assign(n, -1);
  V.top_site.assign(static_cast<size_t>(n) * kVoronoiTopK, -1);
  V.top_value.assign(static_cast<size_t>(n) * kVoronoiTopK, 0.0);
  for (int32_t v = 0; v < n; ++v) {
    std::vector<std::pair<double, int32_t>> vals;
    for (int32_t c = 0; c < static_cast<int32_t>(f.size()); ++c) vals.push_back({-f[c](m.x[v], m.y[v]), c});
    std::sort(vals.begin(), vals.end());
    for (size_t k = 0; k < vals.size() && k < static_cast<size_t>(kVoronoiTopK); ++k) {
      V.top_site[static_cast<size_t>(v) * kVoronoiTopK + k] = vals[k].second;
      V.top_value[static_cast<size_t>(v) * kVoronoiTopK + k] = -vals[k].first;
    }
    V.label[v] = vals[0].second;
  }
  return V;
}

}  // namespace

TEST_CASE("cell partition: linear heat on a grid splits triangles along the exact lines") {
  // Three cells: u0 = x, u1 = y, u2 = 0.6 -> cell 2 is [0,0.6]^2 (area 0.36), cells 0
  // and 1 are the rest split by the diagonal (0.32 each). 0.6 is not a grid line.
  const Mesh m = make_grid(17, 0.3, 4);
  const HeatVoronoi V = linear_heat(m, {[](double x, double) { return x; }, [](double, double y) { return y; },
                                        [](double, double) { return 0.6; }});
  const auto fa = face_areas(m);
  const CellPartition P = partition_cells(m, fa, V, 3);
  CHECK(P.area[0] == doctest::Approx(0.32).epsilon(1e-12));
  CHECK(P.area[1] == doctest::Approx(0.32).epsilon(1e-12));
  CHECK(P.area[2] == doctest::Approx(0.36).epsilon(1e-12));
  CHECK(P.split_faces > 0);
  CHECK(P.fallback_faces == 0);
  // First moments: sum_i b_i x_i = int_C x dA (hat functions reproduce linear functions).
  // Cell 2: int x over [0,0.6]^2 = 0.6 * 0.18 = 0.108. Cell 0 ({x > 0.6, y < x}):
  // int_{0.6}^{1} x * x dx = (1 - 0.216) / 3.
  double mx[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    for (int64_t k = P.offsets[c]; k < P.offsets[c + 1]; ++k) {
      CHECK(P.load[k] > 0);
      if (k > P.offsets[c]) CHECK(P.vertex[k] > P.vertex[k - 1]);
      mx[c] += P.load[k] * m.x[P.vertex[k]];
    }
  }
  CHECK(mx[2] == doctest::Approx(0.108).epsilon(1e-12));
  CHECK(mx[0] == doctest::Approx((1 - 0.216) / 3).epsilon(1e-12));
  // Whole-vertex-star loads would be off by about a grid cell: the split is what makes this exact.
  const auto mass = lumped_mass(m);
  double vertex_area2 = 0;
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (V.label[v] == 2) vertex_area2 += mass[v];
  CHECK(std::abs(vertex_area2 - 0.36) > 1e-3);
}

TEST_CASE("cell partition: single cell gives the lumped mass; missing heat values fall back; bad input") {
  const Mesh m = make_icosphere(2);
  const int32_t n = m.num_vertices();
  HeatVoronoi V;
  V.label.assign(n, 0);
  V.top_site.assign(static_cast<size_t>(n) * kVoronoiTopK, -1);
  V.top_value.assign(static_cast<size_t>(n) * kVoronoiTopK, 0.0);
  for (int32_t v = 0; v < n; ++v) V.top_site[static_cast<size_t>(v) * kVoronoiTopK] = 0;
  const auto fa = face_areas(m), mass = lumped_mass(m);
  const CellPartition P = partition_cells(m, fa, V, 1);
  REQUIRE(P.offsets[1] == n);
  for (int32_t v = 0; v < n; ++v) CHECK(P.load[v] == doctest::Approx(mass[v]).epsilon(1e-12));
  // Vertex 0 in its own cell, but no heat values of cell 1 anywhere: every split
  // triangle falls back to the vertex labels.
  V.label[0] = 1;
  V.top_site[0] = 1;
  const CellPartition Q = partition_cells(m, fa, V, 2);
  CHECK(Q.split_faces == Q.fallback_faces);
  CHECK(Q.area[1] == doctest::Approx(mass[0]).epsilon(1e-12));
  CHECK_THROWS_AS(partition_cells(m, fa, V, 1), Error);                       // label 1 out of range
  CHECK_THROWS_AS(partition_cells(m, std::vector<double>(3, 1.0), V, 2), Error);  // face areas
}

TEST_CASE("cell partition: cell-by-cell loads give the exact areas and moments of the split cells") {
  // The grid and linear heat of the first test: cells 0 and 1 have area 0.32, cell 2
  // (the square [0,0.6]^2) 0.36 and first moment int x = 0.108.
  const Mesh m = make_grid(17, 0.3, 4);
  const HeatVoronoi V = linear_heat(m, {[](double x, double) { return x; }, [](double, double y) { return y; },
                                        [](double, double) { return 0.6; }});
  const auto fa = face_areas(m);
  // Stars with their own face lists, and stars borrowing the centroid fits' (the same lists).
  const CentroidGeometry geo = prepare_centroid_geometry(m);
  const VertexStars own = vertex_stars(m, fa);
  const VertexStars borrowed = vertex_stars(m, geo.vf_offsets, geo.vf_faces, HostVector<double>(fa.begin(), fa.end()));
  for (const VertexStars* stars : {&own, &borrowed}) {
    const VertexStars& st = *stars;
    const int32_t n = m.num_vertices();
    std::vector<double> acc(n, 0.0);
    const double exact_area[3] = {0.32, 0.32, 0.36};
    int64_t fallback = 0;
    double total = 0;
    for (int32_t c = 0; c < 3; ++c) {
      std::vector<int32_t> cell, touched;
      for (int32_t v = 0; v < n; ++v)
        if (V.label[v] == c) cell.push_back(v);
      const double area = accumulate_cell_load(st, V, c, cell, acc, touched, fallback);
      CHECK(area == doctest::Approx(exact_area[c]).epsilon(1e-12));
      double sum = 0, mx = 0;
      for (int32_t v : touched) {
        CHECK(acc[v] > 0);
        sum += acc[v];
        mx += acc[v] * m.x[v];
        acc[v] = 0.0;
      }
      CHECK(sum == doctest::Approx(exact_area[c]).epsilon(1e-12));
      if (c == 2) CHECK(mx == doctest::Approx(0.108).epsilon(1e-12));
      if (c == 0) CHECK(mx == doctest::Approx((1 - 0.216) / 3).epsilon(1e-12));
      // Loads reach across the cell's boundary (split triangles give their corners a share).
      bool outside = false;
      for (int32_t v : touched) outside = outside || V.label[v] != c;
      CHECK(outside);
      total += area;
    }
    CHECK(total == doctest::Approx(1.0).epsilon(1e-12));
    CHECK(fallback == 0);
    for (double a : acc) CHECK(a == 0.0);
    // Without the dense vector: the same exact areas and moment, each touched
    // vertex once with its load beside it, and the slots all -1 again.
    std::vector<int32_t> slot(n, -1);
    int64_t fallback_slots = 0;
    for (int32_t c = 0; c < 3; ++c) {
      std::vector<int32_t> cell, touched;
      std::vector<double> load;
      for (int32_t v = 0; v < n; ++v)
        if (V.label[v] == c) cell.push_back(v);
      const double area = accumulate_cell_load(st, V, c, cell, slot, load, touched, fallback_slots);
      CHECK(area == doctest::Approx(exact_area[c]).epsilon(1e-12));
      REQUIRE(load.size() == touched.size());
      std::vector<int32_t> sorted = touched;
      std::sort(sorted.begin(), sorted.end());
      CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
      double sum = 0, mx = 0;
      for (size_t k = 0; k < touched.size(); ++k) {
        CHECK(load[k] > 0);
        sum += load[k];
        mx += load[k] * m.x[touched[k]];
      }
      CHECK(sum == doctest::Approx(exact_area[c]).epsilon(1e-12));
      if (c == 2) CHECK(mx == doctest::Approx(0.108).epsilon(1e-12));
      if (c == 0) CHECK(mx == doctest::Approx((1 - 0.216) / 3).epsilon(1e-12));
      CHECK(std::count(slot.begin(), slot.end(), -1) == n);
    }
    CHECK(fallback_slots == 0);
  }
}

TEST_CASE("cell areas from the stars: partition_cells' areas bit for bit, the exact areas") {
  // The three cells of the test above (areas 0.32, 0.32, 0.36), on a grid with
  // flipped diagonals too.
  for (double flip : {0.0, 0.4}) {
    CAPTURE(flip);
    const Mesh m = make_grid(17, flip, 4);
    const HeatVoronoi V = linear_heat(m, {[](double x, double) { return x; }, [](double, double y) { return y; },
                                          [](double, double) { return 0.6; }});
    const auto fa = face_areas(m);
    const CellPartition P = partition_cells(m, fa, V, 3);
    HostVector<int64_t> off(4, 0);
    for (int32_t v = 0; v < m.num_vertices(); ++v) ++off[V.label[v] + 1];
    for (int c = 0; c < 3; ++c) off[c + 1] += off[c];
    HostVector<int32_t> verts(m.num_vertices());
    HostVector<int64_t> fill(off.begin(), off.end() - 1);
    for (int32_t v = 0; v < m.num_vertices(); ++v) verts[fill[V.label[v]]++] = v;  // ascending per cell
    const HostVector<double> a = cell_areas(vertex_stars(m, fa), V, off, verts);
    REQUIRE(a.size() == 3);
    for (int c = 0; c < 3; ++c) CHECK(a[c] == P.area[c]);  // bitwise
    CHECK(a[0] == doctest::Approx(0.32).epsilon(1e-12));
    CHECK(a[2] == doctest::Approx(0.36).epsilon(1e-12));
  }
  const Mesh m = make_grid(4);
  HeatVoronoi V = linear_heat(m, {[](double x, double) { return x; }});
  CHECK_THROWS_AS(cell_areas(vertex_stars(m, face_areas(m)), V, {}, {}), Error);
}

TEST_CASE("split rows: the split triangles' corners keep their labels' heat, the loads the exact areas and moments") {
  // The three cells of the tests above (areas 0.32, 0.32, 0.36; cell 2's first
  // moment int x = 0.108). Oracle for the entries: vertex v keeps the entries
  // of its full list whose site labels a corner of some triangle at v with two
  // labels or more (brute force over the faces), in list order.
  const Mesh m = make_grid(17, 0.4, 4);
  const int32_t n = m.num_vertices();
  const HeatVoronoi full = linear_heat(m, {[](double x, double) { return x; }, [](double, double y) { return y; },
                                           [](double, double) { return 0.6; }});
  std::vector<std::vector<int32_t>> split_labels(n);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    if (full.label[v[0]] != full.label[v[1]] || full.label[v[1]] != full.label[v[2]])
      for (int32_t w : v)
        for (int32_t u : v) split_labels[w].push_back(full.label[u]);
  }
  HeatVoronoi V = full;
  keep_split_rows(V, m);
  REQUIRE(V.top_offsets.size() == static_cast<size_t>(n) + 1);
  int32_t next = 0, rows = 0, dropped = 0;
  for (int32_t v = 0; v < n; ++v) {
    CAPTURE(v);
    REQUIRE(V.top_offsets[v] == next);  // in vertex order
    rows += !split_labels[v].empty();
    for (int k = 0; k < kVoronoiTopK; ++k) {
      const size_t e = static_cast<size_t>(v) * kVoronoiTopK + k;
      const auto& l = split_labels[v];
      if (std::find(l.begin(), l.end(), full.top_site[e]) == l.end()) {
        dropped += full.top_site[e] >= 0 && !l.empty();
        continue;
      }
      CHECK(V.top_site[next] == full.top_site[e]);
      CHECK(V.top_value[next] == full.top_value[e]);
      ++next;
    }
  }
  CHECK(V.top_offsets[n] == next);
  CHECK(rows > 0);
  CHECK(rows < n / 2);  // most of the grid's vertices are inside a cell
  CHECK(dropped > 0);   // the third cell's heat where only two meet
  CHECK(V.top_site.size() == static_cast<size_t>(next));
  CHECK(V.top_value.size() == V.top_site.size());
  CHECK(V.label == full.label);
  // The loads read the kept rows only: the exact areas and moment, bit for bit
  // those of the full lists.
  const auto fa = face_areas(m);
  const VertexStars st = vertex_stars(m, fa);
  const double exact_area[3] = {0.32, 0.32, 0.36};
  std::vector<int32_t> slot(n, -1);
  for (int32_t c = 0; c < 3; ++c) {
    std::vector<int32_t> cell;
    for (int32_t v = 0; v < n; ++v)
      if (V.label[v] == c) cell.push_back(v);
    std::vector<int32_t> touched, touched_full;
    std::vector<double> load, load_full;
    int64_t fallback = 0;
    const double area = accumulate_cell_load(st, V, c, cell, slot, load, touched, fallback);
    accumulate_cell_load(st, full, c, cell, slot, load_full, touched_full, fallback);
    CHECK(fallback == 0);
    CHECK(area == doctest::Approx(exact_area[c]).epsilon(1e-12));
    CHECK(touched == touched_full);
    CHECK(load == load_full);
    double mx = 0;
    for (size_t k = 0; k < touched.size(); ++k) mx += load[k] * m.x[touched[k]];
    if (c == 2) CHECK(mx == doctest::Approx(0.108).epsilon(1e-12));
  }
  // What needs every vertex's list refuses the short ones; a second call too.
  CHECK_THROWS_AS(partition_cells(m, fa, V, 3), Error);
  CHECK_THROWS_AS(keep_hottest_only(V), Error);
  CHECK_THROWS_AS(keep_split_rows(V, m), Error);
  HeatVoronoi other = full;
  other.label.pop_back();
  CHECK_THROWS_AS(keep_split_rows(other, m), Error);
}
