// Harmonic patch parameterization from the global factor (pipelines/include/locus/pipelines/param/patch_param.hpp; thesis §4.4, eq. 4.6).
#include "locus/pipelines/param/patch_param.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/error.hpp"

namespace locus {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double dist(const Mesh& m, int32_t a, int32_t b) {
  return std::sqrt((m.x[a] - m.x[b]) * (m.x[a] - m.x[b]) + (m.y[a] - m.y[b]) * (m.y[a] - m.y[b]) +
                   (m.z[a] - m.z[b]) * (m.z[a] - m.z[b]));
}

}  // namespace

double loop_length(const Mesh& m, std::span<const int32_t> loop) {
  double s = 0;
  for (size_t j = 0; j < loop.size(); ++j) s += dist(m, loop[j], loop[(j + 1) % loop.size()]);
  return s;
}

size_t longest_loop(const Mesh& m, const std::vector<std::vector<int32_t>>& loops) {
  size_t best = 0;
  double best_len = -1;
  for (size_t l = 0; l < loops.size(); ++l) {
    const double len = loop_length(m, loops[l]);
    if (len > best_len) {
      best_len = len;
      best = l;
    }
  }
  return best;
}

std::vector<double> circle_layout(const Mesh& m, std::span<const int32_t> loop) {
  const size_t nb = loop.size();
  if (nb < 3) fail(ErrorCode::BadInput, "patch boundary loop has " + std::to_string(nb) + " vertices, need >= 3");
  for (size_t j = 0; j < nb; ++j)
    if (loop[j] < 0 || loop[j] >= m.num_vertices())
      fail(ErrorCode::BadUsage, "boundary loop entry " + std::to_string(j) + " is vertex " + std::to_string(loop[j]) +
                                    ", outside the mesh");
  const double total = loop_length(m, loop);
  if (!(total > 0) || !std::isfinite(total))
    fail(ErrorCode::BadInput, "patch boundary loop has length " + std::to_string(total));
  // Arc-length angles on a circle of the loop's own circumference.
  const double r = total / (2.0 * std::numbers::pi);
  std::vector<double> xy(2 * nb);
  double s = 0;
  for (size_t j = 0; j < nb; ++j) {
    const double a = 2.0 * std::numbers::pi * s / total;
    xy[2 * j] = r * std::cos(a);
    xy[2 * j + 1] = r * std::sin(a);
    s += dist(m, loop[j], loop[(j + 1) % nb]);
  }
  return xy;
}

std::vector<double> circle_neumann_rhs(const Mesh& m, std::span<const int32_t> loop) {
  const size_t nb = loop.size();
  const std::vector<double> xy = circle_layout(m, loop);
  std::vector<double> b(2 * nb);
  for (size_t j = 0; j < nb; ++j) {
    const size_t next = (j + 1) % nb, prev = (j + nb - 1) % nb;
    const double dx = xy[2 * next] - xy[2 * prev], dy = xy[2 * next + 1] - xy[2 * prev + 1];
    b[2 * j] = 0.5 * dy;  // 1/2 (dx, dy)^perp, perp = clockwise rotation (outward normal)
    b[2 * j + 1] = -0.5 * dx;
  }
  return b;
}

UvFlips count_uv_flips(const Mesh& m, std::span<const double> uv) {
  if (!m.is_triangle_mesh()) fail(ErrorCode::BadInput, "uv flips: not a triangle mesh");
  if (uv.size() != 2 * static_cast<size_t>(m.num_vertices()))
    fail(ErrorCode::BadUsage, "uv flips: " + std::to_string(uv.size()) + " uv values for " +
                                  std::to_string(m.num_vertices()) + " vertices");
  const int32_t nf = m.num_faces();
  std::vector<double> area(static_cast<size_t>(nf));
  double mean_abs = 0;
  for (int32_t f = 0; f < nf; ++f) {
    const double* a = &uv[2 * static_cast<size_t>(m.f0[f])];
    const double* b = &uv[2 * static_cast<size_t>(m.f1[f])];
    const double* c = &uv[2 * static_cast<size_t>(m.f2[f])];
    area[f] = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    mean_abs += std::abs(area[f]);
  }
  UvFlips r;
  if (nf == 0) return r;
  mean_abs /= nf;
  const double tiny = 1e-12 * mean_abs;
  int64_t pos = 0, neg = 0;
  for (double a : area) {
    if (!(std::abs(a) > tiny)) ++r.degenerate;  // also catches NaN
    else if (a > 0) ++pos;
    else ++neg;
  }
  r.orientation = pos >= neg ? 1 : -1;
  r.flipped = std::min(pos, neg);
  return r;
}

void normalize_uv(std::span<double> uv) {
  const size_t np = uv.size() / 2;
  if (np == 0) return;
  double cu = 0, cv = 0;
  for (size_t k = 0; k < np; ++k) {
    cu += uv[2 * k];
    cv += uv[2 * k + 1];
  }
  cu /= static_cast<double>(np);
  cv /= static_cast<double>(np);
  double rmax = 0;
  for (size_t k = 0; k < np; ++k) {
    uv[2 * k] -= cu;
    uv[2 * k + 1] -= cv;
    rmax = std::max(rmax, std::hypot(uv[2 * k], uv[2 * k + 1]));
  }
  if (rmax > 0)
    for (double& x : uv) x /= rmax;
}

void solve_patch_uv(const NumericFactor& F, std::span<const int32_t> support, std::span<const double> b,
                    std::span<const int32_t> wanted, std::span<double> uv, SolveWorkspace& ws, SolvePlan* plan_out) {
  if (!F.symbolic) fail(ErrorCode::BadUsage, "patch solve: empty factor");
  if (b.size() != 2 * support.size() || uv.size() != 2 * wanted.size())
    fail(ErrorCode::BadUsage, "patch solve: sizes of b / uv do not match the support / wanted sets");
  SolvePlan plan = plan_subset_solve(*F.symbolic, support, wanted);
  // u and v in lanes 0 and 1 of one 8-lane solve; lanes 2..7 are zero padding.
  std::vector<double> rhs(support.size() * kLanes, 0.0), out(wanted.size() * kLanes);
  for (size_t j = 0; j < support.size(); ++j) {
    rhs[j * kLanes] = b[2 * j];
    rhs[j * kLanes + 1] = b[2 * j + 1];
  }
  solve_planned8(F, plan, rhs, out, ws);
  for (size_t k = 0; k < wanted.size(); ++k) {
    uv[2 * k] = out[k * kLanes];
    uv[2 * k + 1] = out[k * kLanes + 1];
  }
  if (plan_out) *plan_out = std::move(plan);
}

PatchParam parameterize_patch(const NumericFactor& F, const PatchGrower& g, int32_t center, int32_t count,
                              PatchWorkspace& pws, SolveWorkspace& ws) {
  if (!g.mesh) fail(ErrorCode::BadUsage, "patch parameterization: the grower was not prepared");
  const Mesh& m = *g.mesh;
  if (!F.symbolic || F.n() != m.num_vertices())
    fail(ErrorCode::BadUsage, "patch parameterization: the factor has " + std::to_string(F.n()) +
                                  " columns but the mesh has " + std::to_string(m.num_vertices()) + " vertices");
  PatchParam P;
  auto t0 = std::chrono::steady_clock::now();
  P.patch = grow_patch(g, center, ring_patch(count), pws);  // BFS rings (patch_grower.hpp)
  P.grow_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const Mesh& pm = P.patch.mesh;
  const std::vector<std::vector<int32_t>> loops = boundary_loops(pm);
  P.boundary_loops = static_cast<int32_t>(loops.size());
  P.euler_characteristic = static_cast<int64_t>(pm.num_vertices()) - static_cast<int64_t>(unique_edges(pm).e0.size()) +
                           pm.num_faces();
  if (loops.empty())
    fail(ErrorCode::BadInput, mesh_name(m) + ": the patch around vertex " + std::to_string(center) + " with " +
                                  std::to_string(pm.num_vertices()) +
                                  " vertices has no boundary (it is a whole closed component); use a smaller fraction");
  const size_t best = longest_loop(pm, loops);
  P.boundary.reserve(loops[best].size());
  for (int32_t v : loops[best]) P.boundary.push_back(P.patch.vertices[v]);
  const std::vector<double> b = circle_neumann_rhs(m, P.boundary);
  P.rhs_s = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  P.uv_raw.resize(2 * P.patch.vertices.size());
  SolvePlan plan;
  solve_patch_uv(F, P.boundary, b, P.patch.vertices, P.uv_raw, ws, &plan);
  P.solve_s = seconds_since(t0);
  P.forward_columns = plan.forward_columns;
  P.backward_columns = plan.backward_columns;

  t0 = std::chrono::steady_clock::now();
  P.uv = P.uv_raw;
  normalize_uv(P.uv);
  P.flips = count_uv_flips(pm, P.uv);
  P.check_s = seconds_since(t0);
  return P;
}

}  // namespace locus
