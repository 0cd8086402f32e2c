// Tests for pipelines/self_supporting (thesis §2.6, eq. 2.12). Oracles: a
// four-strut pyramid whose equilibrium force follows from statics by hand, and
// the force balance of eq. 2.12 re-evaluated here from the returned forces.
#include <doctest/doctest.h>

#include <cmath>

#include "locus/error.hpp"
#include "locus/pipelines/laplacian/self_supporting.hpp"

using namespace locus;

namespace {

// max over unsupported vertices of ||Σ_j f_ij (v_j - v_i)/|e| + (0,0,F_i)|| / max F.
double force_imbalance(const Mesh& m, const SelfSupportResult& R) {
  const size_t nv = static_cast<size_t>(m.num_vertices());
  std::vector<double> sx(nv, 0), sy(nv, 0), sz(nv, 0);
  for (size_t e = 0; e < R.e0.size(); ++e) {
    const int32_t a = R.e0[e], b = R.e1[e];
    const double dx = R.pos[0][b] - R.pos[0][a], dy = R.pos[1][b] - R.pos[1][a], dz = R.pos[2][b] - R.pos[2][a];
    const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double f = R.forces[e] / l;
    sx[a] += f * dx, sy[a] += f * dy, sz[a] += f * dz;
    sx[b] -= f * dx, sy[b] -= f * dy, sz[b] -= f * dz;
  }
  double worst = 0, fmax = 0;
  for (size_t v = 0; v < nv; ++v) {
    if (R.supported[v]) continue;
    fmax = std::max(fmax, R.load[v]);
    worst = std::max(worst, std::sqrt(sx[v] * sx[v] + sy[v] * sy[v] + (sz[v] + R.load[v]) * (sz[v] + R.load[v])));
  }
  return worst / fmax;
}

}  // namespace

TEST_CASE("pyramid: one loaded apex on four struts, force from statics") {
  Mesh m;
  m.add_vertex(1, 0, 0);
  m.add_vertex(0, 1, 0);
  m.add_vertex(-1, 0, 0);
  m.add_vertex(0, -1, 0);
  const double h = 0.5;
  m.add_vertex(0, 0, h);
  for (int i = 0; i < 4; ++i) m.add_triangle(i, (i + 1) % 4, 4);
  SelfSupportOptions o;
  o.load_density = 2.0;
  const auto R = self_supporting(m, o);
  CHECK(R.converged);
  // Load: a third of each triangle's area.
  const double l = std::sqrt(1 + h * h);
  const double tri_area = 0.5 * std::sqrt(h * h * 2 + 1.0);  // |(b-a) x (apex-a)|/2 for a=(1,0,0), b=(0,1,0)
  const double F = 2.0 * 4 * tri_area / 3;
  CHECK(R.load[4] == doctest::Approx(F).epsilon(1e-12));
  // Statics: 4 f h / l = F, and the input itself is in equilibrium: it must not move.
  const double f = F * l / (4 * h);
  for (size_t e = 0; e < R.e0.size(); ++e)
    if (R.e1[e] == 4) CHECK(R.forces[e] == doctest::Approx(f).epsilon(1e-6));
  CHECK(R.max_displacement_rel < 1e-6);
  CHECK(force_imbalance(m, R) < 1e-10);
}

TEST_CASE("quad vault: compression-only equilibrium near the input") {
  const int n = 10;
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n;
      m.add_vertex(x, y, 0.6 * (1 - x * x) * (1 - y * y) + 0.05 * std::sin(7 * x + 3 * y));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i;
      const int32_t q[4] = {a, a + 1, a + n + 2, a + n + 1};
      m.add_face(q);
    }
  SelfSupportOptions o;
  o.iteration.max_iterations = 300;  // every iterate is an equilibrium; convergence is slow (see the report)
  const auto R = self_supporting(m, o);
  MESSAGE("vault: iterations " << R.iterations << ", residual " << R.residual_rel << ", forces [" << R.min_force << ", "
                               << R.max_force << "], displacement " << R.max_displacement_rel);
  CHECK(R.min_force >= 0.0);
  CHECK(R.residual_rel < 1e-9);
  CHECK(force_imbalance(m, R) < 1e-9);
  CHECK(R.max_displacement_rel < 0.1);
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (!R.supported[v]) CHECK(R.pos[2][v] > 0.0);  // still a vault
}

TEST_CASE("self-supporting rejects closed meshes and unknown supports") {
  Mesh m;
  m.add_vertex(0, 0, 0);
  m.add_vertex(1, 0, 0);
  m.add_vertex(0, 1, 0);
  m.add_vertex(0, 0, 1);
  m.add_triangle(0, 2, 1);
  m.add_triangle(0, 1, 3);
  m.add_triangle(1, 2, 3);
  m.add_triangle(2, 0, 3);
  CHECK_THROWS_AS(self_supporting(m), Error);
  SelfSupportOptions o;
  o.support = "corners";
  CHECK_THROWS_AS(self_supporting(m, o), Error);
}
