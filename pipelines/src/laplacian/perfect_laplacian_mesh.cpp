// Perfect Laplacian of a mesh (thesis §2.3.1–2.3.2): the problem Algorithm 1
// solves, built from a polygon mesh (planar mode: the boundary held on a convex
// loop, b = 0; in space: every boundary loop held, b the integrated
// mean-curvature normal, eq. 2.10), and the result aligned to the input by a
// similarity. The iteration itself is in perfect_laplacian.cpp.
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

void perfect_laplacian_detail::set_target_lengths_in_space(const Mesh& m, PerfectLaplacianProblem& P) {
  const size_t ne = P.e0.size();
  P.target_length.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = P.e0[e], b = P.e1[e];
    P.target_length[e] = std::sqrt((m.x[b] - m.x[a]) * (m.x[b] - m.x[a]) + (m.y[b] - m.y[a]) * (m.y[b] - m.y[a]) +
                                   (m.z[b] - m.z[a]) * (m.z[b] - m.z[a]));
    if (!(P.target_length[e] > 0))
      fail(ErrorCode::BadInput, mesh_name(m) + ": edge (" + std::to_string(a) + ", " + std::to_string(b) + ") has zero length");
  }
}

namespace {

using perfect_laplacian_detail::bbox_diagonal;
using perfect_laplacian_detail::edge_length;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

double align_similarity(int dims, const Coords& p, const Coords& q, Coords& out) {
  const size_t n = p[0].size();
  double cp[3] = {0, 0, 0}, cq[3] = {0, 0, 0};
  for (int k = 0; k < dims; ++k) {
    for (size_t i = 0; i < n; ++i) {
      cp[k] += p[k][i];
      cq[k] += q[k][i];
    }
    if (n) {
      cp[k] /= static_cast<double>(n);
      cq[k] /= static_cast<double>(n);
    }
  }
  double num = 0, den = 0;
  for (int k = 0; k < dims; ++k)
    for (size_t i = 0; i < n; ++i) {
      num += (p[k][i] - cp[k]) * (q[k][i] - cq[k]);
      den += (p[k][i] - cp[k]) * (p[k][i] - cp[k]);
    }
  const double s = den > 0 ? num / den : 1.0;
  for (int k = 0; k < dims; ++k) {
    out[k].resize(n);
    for (size_t i = 0; i < n; ++i) out[k][i] = s * (p[k][i] - cp[k]) + cq[k];
  }
  return s;
}

Coords integrated_mean_curvature_normal(const Mesh& m) {
  Mesh tri;
  const Mesh* t = &m;
  if (!m.is_triangle_mesh()) {
    tri.x = m.x;
    tri.y = m.y;
    tri.z = m.z;
    tri.source = m.source;
    for (int32_t f = 0; f < m.num_faces(); ++f) {
      const auto fv = m.face(f);
      for (size_t c = 1; c + 1 < fv.size(); ++c) tri.add_triangle(fv[0], fv[c], fv[c + 1]);
    }
    t = &tri;
  }
  CscMatrix L;
  try {
    L = cotan_laplacian(*t);
  } catch (const Error& err) {
    fail(err.code(), std::string("mean-curvature normals (cotan Laplacian of the fan triangulation of the faces): ") +
                         err.what());
  }
  const int32_t nv = m.num_vertices();
  const HostVector<double>* x[3] = {&m.x, &m.y, &m.z};
  Coords b;
  for (int k = 0; k < 3; ++k) {
    b[k].assign(static_cast<size_t>(nv), 0.0);
    // Differences, so that each edge adds exactly opposite amounts: Σ_i b_i = 0.
    for (int32_t j = 0; j < nv; ++j)
      for (int64_t q = L.colptr[j] + 1; q < L.colptr[j + 1]; ++q) {
        const int32_t i = L.rowind[q];
        const double d = L.values[q] * ((*x[k])[j] - (*x[k])[i]);
        b[k][i] += d;
        b[k][j] -= d;
      }
  }
  return b;
}

namespace {

using Loops = std::vector<std::vector<int32_t>>;

// Weakly convex loop in the plane (orient = +1 counter-clockwise, -1 clockwise):
// collinear boundary vertices (cross product 0 up to rounding) are allowed.
bool weakly_convex(const Mesh& m, const std::vector<int32_t>& L, double orient) {
  const size_t nb = L.size();
  bool convex = true;
  for (size_t i = 0; i < nb && convex; ++i) {
    const int32_t a = L[(i + nb - 1) % nb], b = L[i], c = L[(i + 1) % nb];
    const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], wx = m.x[c] - m.x[b], wy = m.y[c] - m.y[b];
    const double cr = orient * (ux * wy - uy * wx);
    if (cr < -1e-12 * std::hypot(ux, uy) * std::hypot(wx, wy)) convex = false;
  }
  return convex;
}

// Tutte/Floater need a convex boundary: place the loop on a circle of the
// same perimeter around its centroid, spaced by arc length, same orientation.
void place_loop_on_circle(const Mesh& m, const std::vector<int32_t>& L, double orient, Coords& pos) {
  const size_t nb = L.size();
  double cx = 0, cy = 0, per = 0;
  std::vector<double> arc(nb + 1, 0.0);
  for (size_t i = 0; i < nb; ++i) {
    cx += m.x[L[i]];
    cy += m.y[L[i]];
    const int32_t a = L[i], b = L[(i + 1) % nb];
    per += std::hypot(m.x[b] - m.x[a], m.y[b] - m.y[a]);
    arc[i + 1] = per;
  }
  cx /= static_cast<double>(nb);
  cy /= static_cast<double>(nb);
  const double r = per / (2 * std::numbers::pi);
  const double a0 = std::atan2(m.y[L[0]] - cy, m.x[L[0]] - cx);
  for (size_t i = 0; i < nb; ++i) {
    const double ang = a0 + orient * 2 * std::numbers::pi * arc[i] / per;
    pos[0][L[i]] = cx + r * std::cos(ang);
    pos[1][L[i]] = cy + r * std::sin(ang);
  }
}

// Planar mode (§2.3.1): the one boundary loop is held, on a circle when it is
// not convex. b = 0: planar interior vertices have zero mean curvature (eq. 2.4).
void constrain_planar(const Mesh& m, const Loops& loops, PerfectLaplacianProblem& P, MeshPerfectLaplacianResult& R) {
  if (loops.size() != 1)
    fail(ErrorCode::BadInput, mesh_name(m) + ": planar mode needs exactly one boundary loop (a disk); the mesh has " +
                                  std::to_string(loops.size()));
  const auto& L = loops[0];
  const size_t nb = L.size();
  double area2 = 0;
  for (size_t i = 0; i < nb; ++i) {
    const int32_t a = L[i], b = L[(i + 1) % nb];
    area2 += m.x[a] * m.y[b] - m.x[b] * m.y[a];
  }
  if (!(std::abs(area2) > 0.0))
    fail(ErrorCode::BadInput, mesh_name(m) + ": the boundary loop encloses no area in the plane");
  const double orient = area2 > 0 ? 1.0 : -1.0;
  const bool convex = weakly_convex(m, L, orient);
  for (int32_t v : L) P.fixed[v] = 1;
  if (!convex) {
    R.boundary_on_circle = true;
    place_loop_on_circle(m, L, orient, P.fixed_pos);
  }
}

// In space (§2.3.2): every boundary loop is held, a closed component is pinned
// at its lowest-numbered vertex, and b is the mean-curvature normal (eq. 2.10).
void constrain_space(const Mesh& m, const Loops& loops, PerfectLaplacianProblem& P, MeshPerfectLaplacianResult& R) {
  const int32_t nv = m.num_vertices();
  for (const auto& L : loops)
    for (int32_t v : L) P.fixed[v] = 1;
  std::vector<int32_t> comp;
  const int32_t nc = connected_components(m, comp);
  std::vector<uint8_t> comp_fixed(static_cast<size_t>(std::max(nc, 0)), 0);
  for (int32_t v = 0; v < nv; ++v)
    if (P.fixed[v] && comp[v] >= 0) comp_fixed[comp[v]] = 1;
  for (int32_t v = 0; v < nv; ++v)  // lowest-numbered vertex of a closed component
    if (comp[v] >= 0 && !comp_fixed[comp[v]]) {
      comp_fixed[comp[v]] = 1;
      P.fixed[v] = 1;
      ++R.pinned;
    }
  const auto tb = Clock::now();
  P.b = integrated_mean_curvature_normal(m);
  R.rhs_s = seconds_since(tb);
}

// Displacement of the aligned result from the input, relative to the input's diagonal.
void measure_displacement(int dims, const Coords& input, int32_t nv, MeshPerfectLaplacianResult& R) {
  double sum = 0, mx = 0;
  for (int32_t v = 0; v < nv; ++v) {
    double s = 0;
    for (int k = 0; k < dims; ++k) s += (R.aligned[k][v] - input[k][v]) * (R.aligned[k][v] - input[k][v]);
    const double dv = std::sqrt(s);
    sum += dv;
    mx = std::max(mx, dv);
  }
  const double diag = R.bbox_diagonal > 0 ? R.bbox_diagonal : 1.0;
  R.max_displacement_rel = mx / diag;
  R.mean_displacement_rel = sum / (static_cast<double>(nv) * diag);
}

}  // namespace

MeshPerfectLaplacianResult perfect_laplacian(const Mesh& m, const MeshPerfectLaplacianOptions& opt,
                                             const RunContext& ctx) {
  const auto t0 = Clock::now();
  MeshRequirements req;
  req.triangles = false;
  // Only the edge graph and the boundary vertices matter: non-manifold vertices
  // (several fans, common in real polygon meshes) are fine, so are such edges.
  req.manifold = false;
  req.no_degenerate_faces = false;  // the Laplacian only needs nonzero edge lengths (checked below)
  req.no_unreferenced_vertices = true;
  check_requirements(m, req);
  const int32_t nv = m.num_vertices();
  if (nv == 0 || m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": empty mesh");

  MeshPerfectLaplacianResult R;
  const EdgeIncidence inc = edge_incidence(m);
  R.e0.assign(inc.edges.e0.begin(), inc.edges.e0.end());
  R.e1.assign(inc.edges.e1.begin(), inc.edges.e1.end());
  const size_t ne = R.e0.size();
  const auto loops = boundary_loops(m, inc);
  R.boundary_loops = static_cast<int32_t>(loops.size());

  const auto [zlo, zhi] = std::minmax_element(m.z.begin(), m.z.end());
  const bool planar = opt.planar || *zlo == *zhi;
  R.mode = planar ? "planar" : "space";
  const int dims = planar ? 2 : 3;

  PerfectLaplacianProblem P;
  P.nv = nv;
  P.dims = dims;
  P.e0 = R.e0;
  P.e1 = R.e1;
  Coords input{std::vector<double>(m.x), std::vector<double>(m.y), std::vector<double>(m.z)};
  R.bbox_diagonal = bbox_diagonal(dims, input, static_cast<size_t>(nv));
  P.target_length.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    P.target_length[e] = edge_length(dims, input, P.e0[e], P.e1[e]);
    if (!(P.target_length[e] > 0.0))
      fail(ErrorCode::BadInput, mesh_name(m) + ": edge (" + std::to_string(P.e0[e]) + ", " + std::to_string(P.e1[e]) +
                                    ") has zero length" + (planar ? " in the plane" : "") +
                                    "; Algorithm 1 needs positive edge lengths");
  }
  P.fixed.assign(static_cast<size_t>(nv), 0);
  P.fixed_pos = input;
  if (planar)
    constrain_planar(m, loops, P, R);
  else
    constrain_space(m, loops, P, R);

  R.run = run_perfect_laplacian(P, opt.iteration, ctx);
  if (dims == 2) R.run.pos[2].assign(m.z.begin(), m.z.end());  // the plane the mesh lies in
  R.align_scale = align_similarity(dims, R.run.pos, input, R.aligned);
  if (dims == 2) R.aligned[2].assign(m.z.begin(), m.z.end());
  measure_displacement(dims, input, nv, R);
  R.total_s = seconds_since(t0);
  return R;
}

}  // namespace locus
