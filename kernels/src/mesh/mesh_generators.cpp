// Procedural meshes for tests and benchmarks, and 1:4 midpoint subdivision
// (DESIGN.md "--subdivide K"; the test meshes of the thesis' experiments: spheres,
// tori, planar grids and discs with and without flipped edges).
//
// Every generator orients its faces counter-clockwise seen from outside (closed
// surfaces) or from +z (planar meshes). Random choices use std::mt19937_64, whose
// output sequence is fixed by the standard, turned into doubles by our own bit
// conversion (the standard distributions differ between library vendors), so a seed
// gives the same mesh everywhere.
#include "locus/kernels/mesh/mesh_generators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "locus/kernels/mesh/convex_hull.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

constexpr double kPi = std::numbers::pi;

double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// A triangle mesh straight from flat arrays (faces 3 per triangle).
Mesh triangle_mesh(HostVector<double> x, HostVector<double> y, HostVector<double> z, const std::vector<int32_t>& tri) {
  Mesh m;
  m.x = std::move(x);
  m.y = std::move(y);
  m.z = std::move(z);
  const size_t nf = tri.size() / 3;
  m.face_vertices = tri;
  m.face_offsets.resize(nf + 1);
  m.f0.resize(nf);
  m.f1.resize(nf);
  m.f2.resize(nf);
  for (size_t f = 0; f <= nf; ++f) m.face_offsets[f] = static_cast<int32_t>(3 * f);
  for (size_t f = 0; f < nf; ++f) {
    m.f0[f] = tri[3 * f];
    m.f1[f] = tri[3 * f + 1];
    m.f2[f] = tri[3 * f + 2];
  }
  return m;
}

void require(bool ok, const std::string& message) {
  if (!ok) fail(ErrorCode::BadUsage, message);
}

// Twice the signed area of the planar triangle (a, b, c) (z ignored).
double orient2d(const Mesh& m, int32_t a, int32_t b, int32_t c) {
  return (m.x[b] - m.x[a]) * (m.y[c] - m.y[a]) - (m.y[b] - m.y[a]) * (m.x[c] - m.x[a]);
}

// Flips interior edges of a planar triangle mesh at random: edges are visited in a
// seeded random order, each is flipped with probability `fraction` unless one of its
// two triangles was already changed (so flips never interact) or a new triangle would
// not be positively oriented with a margin (planar and convex quad, so no duplicate
// edge can appear).
void flip_random_edges(Mesh& m, double fraction, uint64_t seed) {
  const EdgeIncidence inc = edge_incidence(m);
  const Edges& E = inc.edges;
  std::vector<int32_t> order;
  for (size_t e = 0; e < E.e0.size(); ++e)
    if (E.face_count[e] == 2) order.push_back(static_cast<int32_t>(e));
  std::mt19937_64 rng(seed);
  for (size_t i = order.size(); i > 1; --i) {  // Fisher-Yates with our own index draw
    const size_t j = static_cast<size_t>(uniform01(rng) * static_cast<double>(i));
    std::swap(order[i - 1], order[std::min(j, i - 1)]);
  }
  std::vector<char> touched(static_cast<size_t>(m.num_faces()), 0);
  int32_t* fv = m.face_vertices.data();
  for (const int32_t e : order) {
    if (!(uniform01(rng) < fraction)) continue;
    const int32_t c1 = inc.edge_corners[inc.edge_corner_offsets[e]];
    const int32_t c2 = inc.edge_corners[inc.edge_corner_offsets[e] + 1];
    const int32_t t1 = c1 / 3, t2 = c2 / 3;
    if (touched[t1] || touched[t2]) continue;
    // t1 = (a, b, c) with a -> b the shared edge, t2 = (b, a, d).
    const int32_t a = fv[c1], b = fv[3 * t1 + (c1 % 3 + 1) % 3], c = fv[3 * t1 + (c1 % 3 + 2) % 3];
    const int32_t d = fv[3 * t2 + (c2 % 3 + 2) % 3];
    if (fv[c2] != b) continue;  // inconsistent orientation: leave it alone
    const double scale = (m.x[c] - m.x[d]) * (m.x[c] - m.x[d]) + (m.y[c] - m.y[d]) * (m.y[c] - m.y[d]);
    if (!(orient2d(m, c, a, d) > 1e-6 * scale) || !(orient2d(m, d, b, c) > 1e-6 * scale)) continue;
    fv[3 * t1] = c, fv[3 * t1 + 1] = a, fv[3 * t1 + 2] = d;
    fv[3 * t2] = d, fv[3 * t2 + 1] = b, fv[3 * t2 + 2] = c;
    touched[t1] = touched[t2] = 1;
  }
  m.rebuild_triangle_arrays();
}

}  // namespace

Mesh subdivide_midpoint(const Mesh& input, int times) {
  require(times >= 0, "subdivide_midpoint: times must be >= 0 (got " + std::to_string(times) + ")");
  Mesh m = input;
  for (int round = 0; round < times; ++round) {
    validate_mesh_arrays(m);
    const int32_t nv = m.num_vertices(), nf = m.num_faces();
    for (int32_t f = 0; f < nf; ++f)
      if (m.face_offsets[f + 1] - m.face_offsets[f] != 3)
        fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " has " +
                                      std::to_string(m.face_offsets[f + 1] - m.face_offsets[f]) +
                                      " vertices; 1:4 midpoint subdivision needs triangles");
    const EdgeIncidence inc = edge_incidence(m);
    const int64_t ne = static_cast<int64_t>(inc.edges.e0.size());
    if (nv + ne > std::numeric_limits<int32_t>::max() || 12 * int64_t(nf) > std::numeric_limits<int32_t>::max())
      fail(ErrorCode::ResourceLimit, mesh_name(m) + ": subdividing " + std::to_string(nf) +
                                         " faces would exceed 2^31-1 vertices or face indices");
    std::vector<double> x(m.x), y(m.y), z(m.z);
    x.resize(nv + ne);
    y.resize(nv + ne);
    z.resize(nv + ne);
    for (int64_t e = 0; e < ne; ++e) {
      const int32_t a = inc.edges.e0[e], b = inc.edges.e1[e];
      x[nv + e] = 0.5 * (m.x[a] + m.x[b]);
      y[nv + e] = 0.5 * (m.y[a] + m.y[b]);
      z[nv + e] = 0.5 * (m.z[a] + m.z[b]);
    }
    std::vector<int32_t> tri(12 * static_cast<size_t>(nf));
    for (int32_t f = 0; f < nf; ++f) {
      const int32_t c = 3 * f;
      const int32_t a = m.face_vertices[c], b = m.face_vertices[c + 1], d = m.face_vertices[c + 2];
      if (inc.corner_edge[c] < 0 || inc.corner_edge[c + 1] < 0 || inc.corner_edge[c + 2] < 0)
        fail(ErrorCode::BadInput, mesh_name(m) + ": face " + std::to_string(f) + " repeats a vertex");
      const int32_t ab = nv + inc.corner_edge[c], bd = nv + inc.corner_edge[c + 1], da = nv + inc.corner_edge[c + 2];
      const int32_t t[12] = {a, ab, da, ab, b, bd, da, bd, d, ab, bd, da};
      std::copy(t, t + 12, tri.begin() + 12 * static_cast<size_t>(f));
    }
    Mesh next = triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
    next.source = m.source;
    m = std::move(next);
  }
  return m;
}

Mesh make_cube_sphere(int32_t n, bool triangulate) {
  if (n < 1) fail(ErrorCode::BadUsage, "make_cube_sphere: n must be at least 1");
  Mesh m;
  // Vertices on the cube's surface by integer coordinates (i, j, k) in [0, n]^3.
  const int64_t side = static_cast<int64_t>(n) + 1;
  std::vector<int32_t> id(static_cast<size_t>(side * side * side), -1);
  auto vertex = [&](int32_t i, int32_t j, int32_t k) {
    int32_t& v = id[static_cast<size_t>((static_cast<int64_t>(i) * side + j) * side + k)];
    if (v < 0) {
      const double x = 2.0 * i / n - 1, y = 2.0 * j / n - 1, z = 2.0 * k / n - 1, l = std::sqrt(x * x + y * y + z * z);
      v = m.num_vertices();
      m.add_vertex(x / l, y / l, z / l);
    }
    return v;
  };
  // Per cube face: the fixed axis and its value, and two in-face axes (a, b) with a x b outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side_hi = 0; side_hi < 2; ++side_hi) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // e_a x e_b = +e_axis
      for (int32_t p = 0; p < n; ++p)
        for (int32_t q = 0; q < n; ++q) {
          int32_t c[4];
          const int32_t pa[4] = {p, p + 1, p + 1, p}, pb[4] = {q, q, q + 1, q + 1};
          for (int s = 0; s < 4; ++s) {
            int32_t ijk[3];
            ijk[axis] = side_hi ? n : 0;
            ijk[a] = pa[s];
            ijk[b] = pb[s];
            c[s] = vertex(ijk[0], ijk[1], ijk[2]);
          }
          if (!side_hi) std::swap(c[1], c[3]);  // the low face looks the other way
          if (triangulate) {
            m.add_triangle(c[0], c[1], c[2]);
            m.add_triangle(c[0], c[2], c[3]);
          } else {
            m.add_face(ConstView<int32_t>(c, 4));
          }
        }
    }
  return m;
}

Mesh make_icosphere(int level, double radius) {
  require(level >= 0 && level <= 12, "make_icosphere: level must be in [0, 12] (got " + std::to_string(level) + ")");
  require(radius > 0 && std::isfinite(radius), "make_icosphere: radius must be finite and > 0");
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<double> x = {-1, 1, -1, 1, 0, 0, 0, 0, g, g, -g, -g};
  std::vector<double> y = {g, g, -g, -g, -1, 1, -1, 1, 0, 0, 0, 0};
  std::vector<double> z = {0, 0, 0, 0, g, g, -g, -g, -1, 1, -1, 1};
  std::vector<int32_t> tri = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6,
                              7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10,
                              8, 6, 7, 9, 8, 1};
  // Outward orientation by construction of the list above; enforce it anyway (the
  // icosahedron is centered, so the face normal must point away from the origin).
  for (size_t f = 0; f < 20; ++f) {
    const int32_t a = tri[3 * f], b = tri[3 * f + 1], c = tri[3 * f + 2];
    const double ux = x[b] - x[a], uy = y[b] - y[a], uz = z[b] - z[a];
    const double wx = x[c] - x[a], wy = y[c] - y[a], wz = z[c] - z[a];
    const double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
    if (nx * (x[a] + x[b] + x[c]) + ny * (y[a] + y[b] + y[c]) + nz * (z[a] + z[b] + z[c]) < 0)
      std::swap(tri[3 * f + 1], tri[3 * f + 2]);
  }
  Mesh m = triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
  auto project = [&](Mesh& s) {
    for (int32_t v = 0; v < s.num_vertices(); ++v) {
      const double len = std::sqrt(s.x[v] * s.x[v] + s.y[v] * s.y[v] + s.z[v] * s.z[v]);
      s.x[v] *= radius / len;
      s.y[v] *= radius / len;
      s.z[v] *= radius / len;
    }
  };
  project(m);
  // Project after every level: the next midpoints then come from spherical triangles,
  // which keeps the triangles close to equilateral.
  for (int l = 0; l < level; ++l) {
    m = subdivide_midpoint(m, 1);
    project(m);
  }
  return m;
}

Mesh make_random_sphere(int32_t n, uint64_t seed) {
  require(n >= 4, "make_random_sphere: need at least 4 points (got " + std::to_string(n) + ")");
  require(n <= (1 << 26), "make_random_sphere: at most 2^26 points (got " + std::to_string(n) + ")");
  // Uniform on the sphere (Archimedes: z uniform in [-1, 1], longitude uniform), then
  // rounded to the 2^-52 grid so that the hull predicates are exact on exactly the
  // coordinates we output. The rounding moves points by < 2e-16 off the sphere.
  std::mt19937_64 rng(seed);
  std::vector<int64_t> X(n), Y(n), Z(n);
  const double grid = 0x1p52;
  for (int32_t i = 0; i < n; ++i) {
    const double zc = 2.0 * uniform01(rng) - 1.0;
    const double phi = 2.0 * kPi * uniform01(rng);
    const double rho = std::sqrt(std::max(0.0, 1.0 - zc * zc));
    X[i] = std::llround(rho * std::cos(phi) * grid);
    Y[i] = std::llround(rho * std::sin(phi) * grid);
    Z[i] = std::llround(zc * grid);
  }
  // The points are i.i.d., so their index order is already a random insertion order.
  std::vector<int32_t> tri = convex_hull_3d(X, Y, Z);
  // Almost always every point is a hull vertex; one that is not (two samples closer
  // than ~1e-8) is dropped so the mesh has no unreferenced vertices.
  std::vector<int32_t> id(static_cast<size_t>(n), -1);
  for (const int32_t v : tri) id[v] = 0;
  std::vector<double> x, y, z;
  for (int32_t i = 0; i < n; ++i)
    if (id[i] == 0) {
      id[i] = static_cast<int32_t>(x.size());
      x.push_back(static_cast<double>(X[i]) / grid);
      y.push_back(static_cast<double>(Y[i]) / grid);
      z.push_back(static_cast<double>(Z[i]) / grid);
    }
  for (int32_t& v : tri) v = id[v];
  return triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
}

namespace {

// nu x nv torus vertices and quads (i, j) -> (i+1, j) -> (i+1, j+1) -> (i, j+1), which
// is counter-clockwise seen from outside: d/du x d/dv points away from the core circle.
void torus_grid(int32_t nu, int32_t nv, double R, double r, const char* who, HostVector<double>& x,
                HostVector<double>& y, HostVector<double>& z, HostVector<int32_t>& quads) {
  require(nu >= 3 && nv >= 3, std::string(who) + ": nu and nv must be >= 3");
  require(int64_t(nu) * nv <= (int64_t(1) << 28), std::string(who) + ": nu * nv must be <= 2^28");
  require(R > r && r > 0 && std::isfinite(R), std::string(who) + ": need R > r > 0");
  x.resize(int64_t(nu) * nv);
  y.resize(x.size());
  z.resize(x.size());
  for (int32_t i = 0; i < nu; ++i)
    for (int32_t j = 0; j < nv; ++j) {
      const double u = 2.0 * kPi * i / nu, v = 2.0 * kPi * j / nv;
      const size_t k = static_cast<size_t>(i) * nv + j;
      x[k] = (R + r * std::cos(v)) * std::cos(u);
      y[k] = (R + r * std::cos(v)) * std::sin(u);
      z[k] = r * std::sin(v);
    }
  quads.clear();
  quads.reserve(4 * x.size());
  for (int32_t i = 0; i < nu; ++i)
    for (int32_t j = 0; j < nv; ++j) {
      const int32_t i1 = (i + 1) % nu, j1 = (j + 1) % nv;
      quads.insert(quads.end(), {i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1});
    }
}

}  // namespace

Mesh make_torus(int32_t nu, int32_t nv, double R, double r) {
  HostVector<double> x, y, z;
  HostVector<int32_t> q;
  torus_grid(nu, nv, R, r, "make_torus", x, y, z, q);
  std::vector<int32_t> tri;
  tri.reserve(q.size() / 4 * 6);
  for (size_t k = 0; k < q.size(); k += 4) tri.insert(tri.end(), {q[k], q[k + 1], q[k + 2], q[k], q[k + 2], q[k + 3]});
  return triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
}

Mesh make_quad_torus(int32_t nu, int32_t nv, double R, double r) {
  Mesh m;
  torus_grid(nu, nv, R, r, "make_quad_torus", m.x, m.y, m.z, m.face_vertices);
  const size_t nf = m.face_vertices.size() / 4;
  m.face_offsets.resize(nf + 1);
  for (size_t f = 0; f <= nf; ++f) m.face_offsets[f] = static_cast<int32_t>(4 * f);
  return m;
}

Mesh make_grid(int32_t n, double flip_fraction, uint64_t seed) {
  require(n >= 1 && n <= 16384, "make_grid: n must be in [1, 16384] (got " + std::to_string(n) + ")");
  require(flip_fraction >= 0 && flip_fraction <= 1, "make_grid: flip_fraction must be in [0, 1]");
  const int32_t s = n + 1;
  std::vector<double> x(static_cast<size_t>(s) * s), y(x.size()), z(x.size(), 0.0);
  for (int32_t j = 0; j < s; ++j)
    for (int32_t i = 0; i < s; ++i) {
      x[static_cast<size_t>(j) * s + i] = static_cast<double>(i) / n;
      y[static_cast<size_t>(j) * s + i] = static_cast<double>(j) / n;
    }
  // Every square is split by one diagonal; either diagonal of a square gives two
  // positively oriented triangles, so a flip is always valid here.
  std::mt19937_64 rng(seed);
  std::vector<int32_t> tri;
  tri.reserve(6 * static_cast<size_t>(n) * n);
  for (int32_t j = 0; j < n; ++j)
    for (int32_t i = 0; i < n; ++i) {
      const int32_t a = j * s + i, b = a + 1, c = a + s + 1, d = a + s;
      if (uniform01(rng) < flip_fraction) tri.insert(tri.end(), {a, b, d, b, c, d});
      else tri.insert(tri.end(), {a, b, c, a, c, d});
    }
  return triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
}

Mesh make_disk(int32_t rings, double flip_fraction, uint64_t seed) {
  require(rings >= 1 && rings <= 8192, "make_disk: rings must be in [1, 8192] (got " + std::to_string(rings) + ")");
  require(flip_fraction >= 0 && flip_fraction <= 1, "make_disk: flip_fraction must be in [0, 1]");
  // Ring k (radius k / rings) has 6k vertices, so every edge is about 1/rings long
  // and the triangles are close to equilateral (a hexagonal pattern bent into circles).
  auto ring_start = [](int32_t k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  const int32_t nv = ring_start(rings + 1);
  std::vector<double> x(nv), y(nv), z(nv, 0.0);
  for (int32_t k = 1; k <= rings; ++k)
    for (int32_t i = 0; i < 6 * k; ++i) {
      const double t = 2.0 * kPi * i / (6.0 * k), rad = static_cast<double>(k) / rings;
      x[ring_start(k) + i] = rad * std::cos(t);
      y[ring_start(k) + i] = rad * std::sin(t);
    }
  std::vector<int32_t> tri;
  tri.reserve(6 * static_cast<size_t>(rings) * rings * 3);
  for (int32_t i = 0; i < 6; ++i) tri.insert(tri.end(), {0, 1 + i, 1 + (i + 1) % 6});
  // Zip ring k-1 to ring k: advance on the ring whose next edge midpoint comes first
  // in angle (never a tie: (2i+1)k = (2j+1)(k-1) has no solution, one side is even).
  for (int32_t k = 2; k <= rings; ++k) {
    const int32_t nin = 6 * (k - 1), nout = 6 * k, bin = ring_start(k - 1), bout = ring_start(k);
    int32_t i = 0, j = 0;
    while (i < nin || j < nout) {
      const bool advance_outer =
          i == nin || (j < nout && static_cast<double>(2 * j + 1) / nout < static_cast<double>(2 * i + 1) / nin);
      const int32_t vin = bin + i % nin, vout = bout + j % nout;
      if (advance_outer) {
        tri.insert(tri.end(), {vin, vout, bout + (j + 1) % nout});
        ++j;
      } else {
        tri.insert(tri.end(), {vin, vout, bin + (i + 1) % nin});
        ++i;
      }
    }
  }
  Mesh m = triangle_mesh(std::move(x), std::move(y), std::move(z), tri);
  if (flip_fraction > 0) flip_random_edges(m, flip_fraction, seed);
  return m;
}

}  // namespace locus
