// Flip-free parameterization (thesis §2.6); see flipfree_param.hpp.
#include "locus/pipelines/laplacian/flipfree_param.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "locus/core/enum_names.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/polygon_laplacian.hpp"

namespace locus {

constexpr EnumNames<ParamMethod, 3> kParamMethods{
    {{ParamMethod::Perfect, "perfect"}, {ParamMethod::Cotan, "cotan"}, {ParamMethod::Uniform, "uniform"}}};

ParamMethod parse_param_method(const std::string& name) {
  return parse_enum_name(name, kParamMethods, "parameterization method");
}

const char* param_method_name(ParamMethod m) { return enum_name(m, kParamMethods); }

PlanarFaceCheck check_planar_faces(const Mesh& m, const std::vector<double>& u, const std::vector<double>& v) {
  PlanarFaceCheck out;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto fv = m.face(f);
    const size_t d = fv.size();
    double area2 = 0, perimeter = 0, shortest = HUGE_VAL, min_sin = 1;
    for (size_t c = 0; c < d; ++c) {
      const int32_t a = fv[(c + d - 1) % d], b = fv[c], e = fv[(c + 1) % d];
      area2 += u[b] * v[e] - u[e] * v[b];
      const double ux = u[b] - u[a], uy = v[b] - v[a], wx = u[e] - u[b], wy = v[e] - v[b];
      const double lw = std::hypot(wx, wy);
      perimeter += lw;
      shortest = std::min(shortest, lw);
      const double den = std::hypot(ux, uy) * lw;
      min_sin = std::min(min_sin, den > 0 ? (ux * wy - uy * wx) / den : 0.0);
    }
    out.min_corner_sin = std::min(out.min_corner_sin, min_sin);
    if (area2 < 0 || min_sin < -1e-12) {
      if (out.flipped_faces++ == 0) out.first_flipped = f;
    } else if (area2 <= 2e-14 * perimeter * perimeter || shortest <= 1e-14 * perimeter) {
      if (out.degenerate_faces++ == 0) out.first_degenerate = f;
    }
  }
  return out;
}

FlipFreeParamResult flipfree_param(const Mesh& m, const FlipFreeParamOptions& opt, const RunContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  MeshRequirements req;
  req.triangles = opt.method == ParamMethod::Cotan;
  req.manifold = true;
  req.no_degenerate_faces = opt.method == ParamMethod::Cotan;
  req.no_unreferenced_vertices = true;
  req.connected = true;
  check_requirements(m, req);
  const EdgeIncidence inc = edge_incidence(m);
  const auto loops = boundary_loops(m, inc);
  if (loops.size() != 1)
    fail(ErrorCode::BadInput, mesh_name(m) + ": parameterization needs a disk (one boundary loop); the mesh has " +
                                  std::to_string(loops.size()));
  const int32_t nv = m.num_vertices();
  const Edges& E = inc.edges;
  const size_t ne = E.e0.size();

  // Boundary on the unit circle by 3-D arc length, in loop order (counter-clockwise).
  const auto& L = loops[0];
  const size_t nb = L.size();
  std::vector<double> arc(nb + 1, 0.0);
  for (size_t i = 0; i < nb; ++i) {
    const int32_t a = L[i], b = L[(i + 1) % nb];
    arc[i + 1] = arc[i] + std::sqrt((m.x[b] - m.x[a]) * (m.x[b] - m.x[a]) + (m.y[b] - m.y[a]) * (m.y[b] - m.y[a]) +
                                    (m.z[b] - m.z[a]) * (m.z[b] - m.z[a]));
  }
  if (!(arc[nb] > 0)) fail(ErrorCode::BadInput, mesh_name(m) + ": the boundary loop has zero length");
  Coords fixed_pos;
  fixed_pos[0].assign(static_cast<size_t>(nv), 0.0);
  fixed_pos[1].assign(static_cast<size_t>(nv), 0.0);
  std::vector<uint8_t> fixed(static_cast<size_t>(nv), 0);
  for (size_t i = 0; i < nb; ++i) {
    const double ang = 2 * std::numbers::pi * arc[i] / arc[nb];
    fixed_pos[0][L[i]] = std::cos(ang);
    fixed_pos[1][L[i]] = std::sin(ang);
    fixed[L[i]] = 1;
  }

  FlipFreeParamResult R;
  Coords uv;
  std::vector<double> w;
  if (opt.method == ParamMethod::Perfect) {
    PerfectLaplacianProblem P;
    P.nv = nv;
    P.dims = 2;
    P.e0.assign(E.e0.begin(), E.e0.end());
    P.e1.assign(E.e1.begin(), E.e1.end());
    P.fixed = fixed;
    P.fixed_pos = fixed_pos;
    perfect_laplacian_detail::set_target_lengths_in_space(m, P);
    PerfectLaplacianResult run = run_perfect_laplacian(P, opt.iteration, ctx);
    uv = std::move(run.pos);
    w = std::move(run.weights);
    R.converged = run.converged;
    R.iterations = run.iterations;
    R.zero_weights = run.zero_weights;
    R.first_iter_s = run.first_iter_s;
    R.iter_s = run.iter_s;
  } else {
    w.assign(ne, 1.0);
    EmbeddingSystemOptions so;
    if (opt.method == ParamMethod::Cotan) {
      const CscMatrix Lc = cotan_laplacian(m);
      // L_C's pattern holds edge (e0, e1) in column e0 (kernels/include/locus/kernels/mesh/mesh_operators.hpp).
      for (size_t e = 0; e < ne; ++e) {
        const int32_t a = E.e0[e], b = E.e1[e];
        const auto first = Lc.rowind.begin() + Lc.colptr[a], last = Lc.rowind.begin() + Lc.colptr[a + 1];
        const auto it = std::lower_bound(first + 1, last, b);
        if (it == last || *it != b) fail(ErrorCode::Internal, "cotan Laplacian lacks an edge of the mesh");
        w[e] = Lc.values[it - Lc.rowind.begin()];
        if (w[e] < 0) ++R.negative_weights;
      }
      so.allow_negative_weights = true;
    }
    EmbeddingSystem sys(nv, E.e0, E.e1, fixed, so);
    sys.factor(w, ctx);
    sys.solve(2, fixed_pos, Coords{}, 1.0, uv);
    R.iterations = 1;
  }
  R.min_weight = w.empty() ? 0.0 : *std::min_element(w.begin(), w.end());
  R.faces = check_planar_faces(m, uv[0], uv[1]);
  R.uv.resize(2 * static_cast<size_t>(nv));
  for (int32_t v = 0; v < nv; ++v) {
    R.uv[2 * static_cast<size_t>(v)] = uv[0][v];
    R.uv[2 * static_cast<size_t>(v) + 1] = uv[1][v];
  }
  R.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return R;
}

}  // namespace locus
