// Circle-boundary harmonic patch map from the factor-once update (pipelines/include/locus/pipelines/param/patch_param_circle.hpp).
#include "locus/pipelines/param/patch_param_circle.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Marks of DiskPatchWorkspace::mark while filling holes.
constexpr int32_t kPatch = 1, kOutside = 2, kHole = 3;

// V - E + F of a patch whose edges all have one or two faces (boundary_loops
// checked that): E = (3F + boundary edges) / 2, no edge list needed.
int64_t euler_characteristic(const Mesh& pm, const std::vector<std::vector<int32_t>>& loops) {
  int64_t boundary_edges = 0;
  for (const auto& l : loops) boundary_edges += static_cast<int64_t>(l.size());
  const int64_t f = pm.num_faces();
  return static_cast<int64_t>(pm.num_vertices()) - (3 * f + boundary_edges) / 2 + f;
}

std::string patch_name(const Mesh& m, int32_t center, size_t nv) {
  return mesh_name(m) + ": the patch of " + std::to_string(nv) + " vertices around vertex " + std::to_string(center);
}

}  // namespace

DiskPatch grow_disk_patch(const PatchGrower& g, int32_t center, int32_t count, DiskPatchWorkspace& ws) {
  if (!g.mesh) fail(ErrorCode::BadUsage, "disk patch: the grower was not prepared");
  const Mesh& m = *g.mesh;
  DiskPatch d;
  d.patch = grow_patch(g, center, ring_patch(count), ws.grow);  // BFS rings (patch_grower.hpp)
  if (d.patch.mesh.num_faces() == 0)
    fail(ErrorCode::BadInput, mesh_name(m) + ": the BFS patch of " + std::to_string(count) + " vertices around vertex " +
                                  std::to_string(center) + " holds no whole face; use a larger fraction");
  std::vector<std::vector<int32_t>> loops = boundary_loops(d.patch.mesh);
  if (loops.empty())
    fail(ErrorCode::BadInput, patch_name(m, center, d.patch.vertices.size()) +
                                  " has no boundary (it is a whole closed component); use a smaller fraction");
  size_t outer = longest_loop(d.patch.mesh, loops);

  if (loops.size() > 1) {
    // Fill the holes: BFS in the complement from every non-outer loop, never
    // crossing the patch; touching a neighbor of the outer loop's outside (or
    // growing past the patch's own size) means the "hole" is not enclosed.
    if (ws.mark.size() != static_cast<size_t>(m.num_vertices())) ws.mark.assign(m.num_vertices(), -1);
    std::vector<int32_t> touched, added;
    const auto& off = g.adjacency.offsets;
    const auto& nb = g.adjacency.neighbors;
    for (int32_t v : d.patch.vertices) {
      ws.mark[v] = kPatch;
      touched.push_back(v);
    }
    for (int32_t lv : loops[outer]) {
      const int32_t v = d.patch.vertices[lv];
      for (int64_t k = off[v]; k < off[v + 1]; ++k)
        if (ws.mark[nb[k]] == -1) {
          ws.mark[nb[k]] = kOutside;
          touched.push_back(nb[k]);
        }
    }
    const size_t cap = std::max<size_t>(d.patch.vertices.size(), 64);
    bool enclosed = true;
    std::vector<int32_t> stack;
    for (size_t l = 0; l < loops.size() && enclosed; ++l) {
      if (l == outer) continue;
      for (int32_t lv : loops[l]) {
        const int32_t v = d.patch.vertices[lv];
        for (int64_t k = off[v]; k < off[v + 1] && enclosed; ++k) {
          const int32_t u = nb[k];
          if (ws.mark[u] == kOutside) enclosed = false;
          if (ws.mark[u] != -1) continue;
          ws.mark[u] = kHole;
          touched.push_back(u);
          added.push_back(u);
          stack.push_back(u);
          while (!stack.empty() && enclosed) {
            const int32_t w = stack.back();
            stack.pop_back();
            for (int64_t q = off[w]; q < off[w + 1]; ++q) {
              const int32_t x = nb[q];
              if (ws.mark[x] == kOutside || added.size() > cap) {
                enclosed = false;
                break;
              }
              if (ws.mark[x] != -1) continue;
              ws.mark[x] = kHole;
              touched.push_back(x);
              added.push_back(x);
              stack.push_back(x);
            }
          }
        }
        if (!enclosed) break;
      }
      if (enclosed) ++d.holes_filled;
    }
    for (int32_t v : touched) ws.mark[v] = -1;
    if (!enclosed)
      fail(ErrorCode::BadInput, patch_name(m, center, d.patch.vertices.size()) + " has " +
                                    std::to_string(loops.size()) +
                                    " boundary loops and a hole that is not enclosed by it (the patch is not "
                                    "disk-like); use the Neumann method (--boundary neumann) or another fraction");
    const int32_t rings = d.patch.rings;
    std::vector<int32_t> vertices = d.patch.vertices;
    vertices.insert(vertices.end(), added.begin(), added.end());
    d.vertices_added = static_cast<int32_t>(added.size());
    d.patch = extract_patch(g, vertices, ws.grow);
    d.patch.rings = rings;
    loops = boundary_loops(d.patch.mesh);
    if (loops.size() != 1)
      fail(ErrorCode::BadInput, patch_name(m, center, d.patch.vertices.size()) + " still has " +
                                    std::to_string(loops.size()) +
                                    " boundary loops after filling its holes (not disk-like); use the Neumann "
                                    "method (--boundary neumann) or another fraction");
    outer = 0;
  }
  d.euler_characteristic = euler_characteristic(d.patch.mesh, loops);
  d.boundary.reserve(loops[outer].size());
  for (int32_t v : loops[outer]) d.boundary.push_back(d.patch.vertices[v]);
  d.boundary_local = std::move(loops[outer]);
  return d;
}

CircleDirichletSystem circle_dirichlet_system(const CscMatrix& K, const DiskPatch& p, DiskPatchWorkspace& ws) {
  const int32_t n = K.ncols;
  if (ws.mark.size() != static_cast<size_t>(n)) ws.mark.assign(n, -1);
  CircleDirichletSystem sys;
  // Marks: boundary loop position j -> -2 - j; interior -> local index (set
  // after sorting); outside the patch -1.
  for (size_t j = 0; j < p.boundary.size(); ++j) {
    const int32_t v = p.boundary[j];
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "circle map: boundary vertex " + std::to_string(v) + " outside K");
    ws.mark[v] = -2 - static_cast<int32_t>(j);
  }
  for (int32_t v : p.patch.vertices) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "circle map: patch vertex " + std::to_string(v) + " outside K");
    if (ws.mark[v] == -1) sys.interior.push_back(v);
  }
  std::sort(sys.interior.begin(), sys.interior.end());
  const size_t ni = sys.interior.size();
  for (size_t a = 0; a < ni; ++a) ws.mark[sys.interior[a]] = static_cast<int32_t>(a);
  sys.boundary_uv = circle_layout(p.patch.mesh, p.boundary_local);
  sys.rhs.assign(2 * ni, 0.0);
  sys.mass.assign(ni, 0.0);
  // Every entry K(r, c) = K(c, r) with both ends in the patch, found in the
  // columns of I and B: it adds to the row sums of its interior ends and, for
  // an interior-boundary pair, moves the boundary value to the right-hand side.
  auto scan = [&](int32_t c) {
    const int32_t mc = ws.mark[c];
    for (int64_t k = K.colptr[c]; k < K.colptr[c + 1]; ++k) {
      const int32_t r = K.rowind[k];
      const int32_t mr = ws.mark[r];
      const double v = K.values[k];
      if (r == c) {
        if (mc >= 0) sys.mass[mc] += v;
        continue;
      }
      if (mc >= 0) sys.mass[mc] += v;
      if (mr >= 0) sys.mass[mr] += v;
      if (mc <= -2 && mr >= 0) {
        const size_t j = static_cast<size_t>(-2 - mc);
        sys.rhs[2 * mr] -= v * sys.boundary_uv[2 * j];
        sys.rhs[2 * mr + 1] -= v * sys.boundary_uv[2 * j + 1];
      } else if (mc >= 0 && mr <= -2) {
        const size_t j = static_cast<size_t>(-2 - mr);
        sys.rhs[2 * mc] -= v * sys.boundary_uv[2 * j];
        sys.rhs[2 * mc + 1] -= v * sys.boundary_uv[2 * j + 1];
      }
    }
  };
  for (int32_t v : sys.interior) scan(v);
  for (int32_t v : p.boundary) scan(v);
  for (int32_t v : sys.interior) ws.mark[v] = -1;
  for (int32_t v : p.boundary) ws.mark[v] = -1;
  return sys;
}

namespace {

// y = (K - diag(mass)) x for two interleaved lanes, K lower CSC.
void apply_harmonic(const CscMatrix& K, std::span<const double> mass, const double* x, double* y) {
  const int32_t n = K.ncols;
  for (int32_t i = 0; i < n; ++i) {
    y[2 * i] = -mass[i] * x[2 * i];
    y[2 * i + 1] = -mass[i] * x[2 * i + 1];
  }
  for (int32_t c = 0; c < n; ++c)
    for (int64_t k = K.colptr[c]; k < K.colptr[c + 1]; ++k) {
      const int32_t r = K.rowind[k];
      const double v = K.values[k];
      y[2 * r] += v * x[2 * c];
      y[2 * r + 1] += v * x[2 * c + 1];
      if (r != c) {
        y[2 * c] += v * x[2 * r];
        y[2 * c + 1] += v * x[2 * r + 1];
      }
    }
}

}  // namespace

int solve_circle_dirichlet(const NumericFactor& F, const CscMatrix& K_II, const CircleDirichletSystem& sys,
                           std::span<double> uv, std::span<double> work) {
  const size_t ni = sys.interior.size();
  if (static_cast<size_t>(F.n()) != ni || static_cast<size_t>(K_II.ncols) != ni || uv.size() != 2 * ni ||
      sys.rhs.size() != 2 * ni || sys.mass.size() != ni)
    fail(ErrorCode::BadUsage, "circle map: the factor has " + std::to_string(F.n()) + " columns and K_II " +
                                  std::to_string(K_II.ncols) + " for " + std::to_string(ni) +
                                  " interior vertices (or uv / rhs sizes differ)");
  std::vector<double> x8(ni * kLanes, 0.0);
  std::vector<double> own;
  if (work.empty()) {
    own.resize(solve_work_size(F, kLanes));
    work = own;
  }
  // z = K_II^-1 r for the two lanes (u, v) of one 8-lane solve.
  auto precondition = [&](const std::vector<double>& r, std::vector<double>& z) {
    std::fill(x8.begin(), x8.end(), 0.0);
    for (size_t a = 0; a < ni; ++a) {
      x8[a * kLanes] = r[2 * a];
      x8[a * kLanes + 1] = r[2 * a + 1];
    }
    solve8(F, x8, work);
    for (size_t a = 0; a < ni; ++a) {
      z[2 * a] = x8[a * kLanes];
      z[2 * a + 1] = x8[a * kLanes + 1];
    }
  };
  // x0 = K_II^-1 b, the map of the regularized operator; then conjugate
  // gradients on (K_II - eps M_I) x = b preconditioned by the same factor: the
  // preconditioned spectrum lies in [1 - delta, 1], delta = eps M / lambda_min
  // (a few percent for a 10k-vertex patch), so each step gains ~delta / 4.
  std::vector<double> x(2 * ni), r(2 * ni), z(2 * ni), p(2 * ni), q(2 * ni);
  precondition(sys.rhs, x);
  apply_harmonic(K_II, sys.mass, x.data(), q.data());
  for (size_t k = 0; k < 2 * ni; ++k) r[k] = sys.rhs[k] - q[k];
  precondition(r, z);
  p = z;
  double rz[2] = {0, 0};
  for (size_t a = 0; a < ni; ++a)
    for (int l = 0; l < 2; ++l) rz[l] += r[2 * a + l] * z[2 * a + l];
  int steps = 0;
  for (; steps < 30; ++steps) {
    apply_harmonic(K_II, sys.mass, p.data(), q.data());
    double pq[2] = {0, 0};
    for (size_t a = 0; a < ni; ++a)
      for (int l = 0; l < 2; ++l) pq[l] += p[2 * a + l] * q[2 * a + l];
    double alpha[2], step = 0, size = 0;
    for (int l = 0; l < 2; ++l) alpha[l] = pq[l] > 0 ? rz[l] / pq[l] : 0.0;
    for (size_t a = 0; a < ni; ++a)
      for (int l = 0; l < 2; ++l) {
        const size_t k = 2 * a + l;
        x[k] += alpha[l] * p[k];
        r[k] -= alpha[l] * q[k];
        step = std::max(step, std::abs(alpha[l] * p[k]));
        size = std::max(size, std::abs(x[k]));
      }
    if (!(step > 1e-10 * size)) {
      ++steps;
      break;
    }
    precondition(r, z);
    double rz_new[2] = {0, 0};
    for (size_t a = 0; a < ni; ++a)
      for (int l = 0; l < 2; ++l) rz_new[l] += r[2 * a + l] * z[2 * a + l];
    for (size_t a = 0; a < ni; ++a)
      for (int l = 0; l < 2; ++l) {
        const double beta = rz[l] > 0 ? rz_new[l] / rz[l] : 0.0;
        p[2 * a + l] = z[2 * a + l] + beta * p[2 * a + l];
      }
    rz[0] = rz_new[0];
    rz[1] = rz_new[1];
  }
  for (size_t k = 0; k < 2 * ni; ++k) {
    if (!std::isfinite(x[k])) fail(ErrorCode::Numerical, "circle map: the harmonic map is not finite");
    uv[k] = x[k];
  }
  return steps;
}

std::vector<double> assemble_patch_uv(const DiskPatch& p, const CircleDirichletSystem& sys,
                                      std::span<const double> uv_interior) {
  const size_t np = p.patch.vertices.size();
  std::vector<double> uv(2 * np, 0.0);
  // Patch-local positions: boundary from the circle, interior by binary search
  // in the sorted interior (no n-sized map needed).
  std::vector<char> on_loop(np, 0);
  for (size_t j = 0; j < p.boundary_local.size(); ++j) {
    const int32_t k = p.boundary_local[j];
    on_loop[k] = 1;
    uv[2 * k] = sys.boundary_uv[2 * j];
    uv[2 * k + 1] = sys.boundary_uv[2 * j + 1];
  }
  for (size_t k = 0; k < np; ++k) {
    if (on_loop[k]) continue;
    const auto it = std::lower_bound(sys.interior.begin(), sys.interior.end(), p.patch.vertices[k]);
    if (it == sys.interior.end() || *it != p.patch.vertices[k])
      fail(ErrorCode::BadUsage, "circle map: patch vertex " + std::to_string(p.patch.vertices[k]) +
                                    " is neither interior nor on the boundary loop");
    const size_t a = static_cast<size_t>(it - sys.interior.begin());
    uv[2 * k] = uv_interior[2 * a];
    uv[2 * k + 1] = uv_interior[2 * a + 1];
  }
  return uv;
}

CirclePatchParameterizer::CirclePatchParameterizer(const NumericFactor& F, const CscMatrix& K, const PatchGrower& g)
    : g_(g), K_(K), updater_(F, K) {
  if (!g.mesh) fail(ErrorCode::BadUsage, "circle map: the grower was not prepared");
  if (F.n() != g.mesh->num_vertices() || K.ncols != g.mesh->num_vertices())
    fail(ErrorCode::BadUsage, "circle map: the factor has " + std::to_string(F.n()) + " columns and K " +
                                  std::to_string(K.ncols) + " but the mesh has " +
                                  std::to_string(g.mesh->num_vertices()) + " vertices");
}

CirclePatchParam CirclePatchParameterizer::parameterize(int32_t center, int32_t count, const RunContext& ctx) {
  CirclePatchParam P;
  auto t0 = std::chrono::steady_clock::now();
  P.disk = grow_disk_patch(g_, center, count, ws_);
  P.grow_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const CircleDirichletSystem sys = circle_dirichlet_system(K_, P.disk, ws_);
  P.interior = static_cast<int32_t>(sys.interior.size());
  if (sys.interior.empty())
    fail(ErrorCode::BadInput, patch_name(*g_.mesh, center, P.disk.patch.vertices.size()) +
                                  " has no interior vertex; use a larger fraction");
  P.system_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const FactorUpdate U = updater_.update(sys.interior, ctx);
  P.update = U.stats;
  P.update_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  std::vector<double> uv_int(2 * sys.interior.size());
  P.refinement_steps = solve_circle_dirichlet(U.factor, U.A_sub, sys, uv_int);
  P.uv_raw = assemble_patch_uv(P.disk, sys, uv_int);
  P.solve_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  P.uv = P.uv_raw;
  normalize_uv(P.uv);
  P.flips = count_uv_flips(P.disk.patch.mesh, P.uv);
  P.check_s = seconds_since(t0);
  return P;
}

}  // namespace locus
