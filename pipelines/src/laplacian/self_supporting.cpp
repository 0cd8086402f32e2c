// Self-supporting surfaces with Algorithm 1 (thesis §2.6, eq. 2.12); see self_supporting.hpp.
#include "locus/pipelines/laplacian/self_supporting.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/polygon_laplacian.hpp"

namespace locus {

namespace {

// Supported vertices: every boundary loop. Every component needs a support, or
// its heights are undetermined (BadInput naming a vertex of it).
std::vector<uint8_t> boundary_supports(const Mesh& m, const std::vector<std::vector<int32_t>>& loops) {
  const int32_t nv = m.num_vertices();
  std::vector<uint8_t> supported(static_cast<size_t>(nv), 0);
  for (const auto& L : loops)
    for (int32_t v : L) supported[v] = 1;
  std::vector<int32_t> comp;
  const int32_t nc = connected_components(m, comp);
  std::vector<uint8_t> comp_ok(static_cast<size_t>(std::max(nc, 0)), 0);
  for (int32_t v = 0; v < nv; ++v)
    if (supported[v]) comp_ok[comp[v]] = 1;
  for (int32_t v = 0; v < nv; ++v)
    if (!comp_ok[comp[v]])
      fail(ErrorCode::BadInput, mesh_name(m) + ": the component of vertex " + std::to_string(v) + " has no boundary to support it");
  return supported;
}

// Dead load: vertex share of the incident face areas; 0 at supports.
std::vector<double> dead_load(const Mesh& m, double load_density, const std::vector<uint8_t>& supported) {
  std::vector<double> load(static_cast<size_t>(m.num_vertices()), 0.0);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    const auto [ax, ay, az] = face_vector_area(m, f);
    const double area = 0.5 * std::sqrt(ax * ax + ay * ay + az * az);
    for (int32_t v : fv) load[v] += load_density * area / static_cast<double>(fv.size());
  }
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (supported[v]) load[v] = 0.0;  // carried by the support directly
  return load;
}

// Algorithm 1 in space: supports fixed, b = (0, 0, -F), the input edge lengths as targets.
PerfectLaplacianProblem support_problem(const Mesh& m, const SelfSupportResult& R) {
  const int32_t nv = m.num_vertices();
  PerfectLaplacianProblem P;
  P.nv = nv;
  P.dims = 3;
  P.e0 = R.e0;
  P.e1 = R.e1;
  P.fixed = R.supported;
  P.fixed_pos = Coords{std::vector<double>(m.x), std::vector<double>(m.y), std::vector<double>(m.z)};
  P.b[0].assign(static_cast<size_t>(nv), 0.0);
  P.b[1].assign(static_cast<size_t>(nv), 0.0);
  P.b[2].resize(static_cast<size_t>(nv));
  for (int32_t v = 0; v < nv; ++v) P.b[2][v] = -R.load[v];
  perfect_laplacian_detail::set_target_lengths_in_space(m, P);
  return P;
}

// Forces f_e = ω_raw ||e|| and their range over edges with an unsupported end.
void measure_forces(const std::vector<double>& raw, SelfSupportResult& R) {
  const size_t ne = R.e0.size();
  R.forces.resize(ne);
  R.min_force = HUGE_VAL;
  for (size_t e = 0; e < ne; ++e) {
    const int32_t a = R.e0[e], b = R.e1[e];
    double l2 = 0;
    for (int k = 0; k < 3; ++k) l2 += (R.pos[k][b] - R.pos[k][a]) * (R.pos[k][b] - R.pos[k][a]);
    R.forces[e] = raw[e] * std::sqrt(l2);
    if (R.supported[a] && R.supported[b]) continue;  // support to support: carried by the supports
    R.min_force = std::min(R.min_force, R.forces[e]);
    R.max_force = std::max(R.max_force, R.forces[e]);
  }
  if (R.min_force == HUGE_VAL) R.min_force = 0;
  for (size_t e = 0; e < ne; ++e)
    if (!(R.supported[R.e0[e]] && R.supported[R.e1[e]]) && R.forces[e] <= 1e-8 * R.max_force) ++R.zero_forces;
}

// Equilibrium residual, edge by edge (eq. 2.12), relative to the largest load.
void measure_residual(int32_t nv, const std::vector<double>& raw, SelfSupportResult& R) {
  Coords lv;
  apply_edge_laplacian(nv, R.e0, R.e1, raw, 3, R.pos, lv);
  double worst = 0, fmax = 0;
  for (int32_t v = 0; v < nv; ++v) {
    if (R.supported[v]) continue;
    fmax = std::max(fmax, R.load[v]);
    const double rz = lv[2][v] + R.load[v];
    worst = std::max(worst, std::sqrt(lv[0][v] * lv[0][v] + lv[1][v] * lv[1][v] + rz * rz));
  }
  R.residual_rel = fmax > 0 ? worst / fmax : worst;
}

// Displacement from the input relative to its bounding-box diagonal (no alignment: supports fixed).
void measure_displacement(const Mesh& m, SelfSupportResult& R) {
  const int32_t nv = m.num_vertices();
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const HostVector<double>& c = k == 0 ? m.x : k == 1 ? m.y : m.z;
    const auto [lo, hi] = std::minmax_element(c.begin(), c.end());
    d2 += (*hi - *lo) * (*hi - *lo);
  }
  const double diag = d2 > 0 ? std::sqrt(d2) : 1.0;
  double sum = 0, mx = 0;
  for (int32_t v = 0; v < nv; ++v) {
    const double d = std::sqrt((R.pos[0][v] - m.x[v]) * (R.pos[0][v] - m.x[v]) + (R.pos[1][v] - m.y[v]) * (R.pos[1][v] - m.y[v]) +
                               (R.pos[2][v] - m.z[v]) * (R.pos[2][v] - m.z[v]));
    sum += d;
    mx = std::max(mx, d);
  }
  R.max_displacement_rel = mx / diag;
  R.mean_displacement_rel = sum / (nv * diag);
}

}  // namespace

SelfSupportResult self_supporting(const Mesh& m, const SelfSupportOptions& opt, const RunContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.support != "boundary")
    fail(ErrorCode::BadUsage, "self-supporting: unknown support '" + opt.support + "' (only 'boundary')");
  if (!(opt.load_density > 0) || !std::isfinite(opt.load_density))
    fail(ErrorCode::BadUsage, "self-supporting: the load density must be positive");
  MeshRequirements req;
  req.triangles = false;
  req.manifold = true;
  req.no_degenerate_faces = false;
  req.no_unreferenced_vertices = true;
  check_requirements(m, req);
  const int32_t nv = m.num_vertices();
  const EdgeIncidence inc = edge_incidence(m);
  const auto loops = boundary_loops(m, inc);
  if (loops.empty()) fail(ErrorCode::BadInput, mesh_name(m) + ": closed mesh; self-supporting needs supported boundary vertices");

  SelfSupportResult R;
  R.e0.assign(inc.edges.e0.begin(), inc.edges.e0.end());
  R.e1.assign(inc.edges.e1.begin(), inc.edges.e1.end());
  const size_t ne = R.e0.size();
  R.supported = boundary_supports(m, loops);
  R.load = dead_load(m, opt.load_density, R.supported);
  PerfectLaplacianResult run = run_perfect_laplacian(support_problem(m, R), opt.iteration, ctx);
  R.converged = run.converged;
  R.iterations = run.iterations;
  R.first_iter_s = run.first_iter_s;
  R.iter_s = run.iter_s;
  R.pos = std::move(run.pos);

  // Raw weights balance the actual loads: ω_raw = ω / rhs_scale.
  std::vector<double> raw(ne);
  for (size_t e = 0; e < ne; ++e) raw[e] = run.weights[e] / run.rhs_scale;
  measure_forces(raw, R);
  measure_residual(nv, raw, R);
  measure_displacement(m, R);
  R.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return R;
}

}  // namespace locus
