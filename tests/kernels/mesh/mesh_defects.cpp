// Tests for kernels/mesh/mesh_defects.{hpp,cpp}: the needle count and the
// first needle, reduced over threads, against an oracle written here (each
// face's angles by acos of the normalized dot products, a face at a time) at
// 1, 2 and 4 threads.
#include <doctest/doctest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "locus/kernels/mesh/mesh_defects.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"

using namespace locus;

namespace {

// The faces with an angle within kNeedleAngle of 0 or pi, in face order.
std::vector<int32_t> oracle_needles(const Mesh& m) {
  std::vector<int32_t> out;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    bool needle = false;
    for (int k = 0; k < 3; ++k) {
      const int32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      const double u[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
      const double w[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
      const double nu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      const double nw = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      const double angle = std::acos(std::clamp((u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (nu * nw), -1.0, 1.0));
      needle = needle || angle < kNeedleAngle || angle > M_PI - kNeedleAngle;
    }
    if (needle) out.push_back(f);
  }
  return out;
}

}  // namespace

TEST_CASE("mesh defects: needles counted and the first found for any number of threads") {
  Mesh m = make_grid(200);  // 80,000 faces: many ranges per thread
  const double h = 1.0 / 200;
  // Needles across the face order: a face's third corner moved onto the
  // midpoint of its other two, lifted by 1e-8 h (an angle of ~pi - 4e-8;
  // an area far above the zero-area threshold).
  for (int32_t f : {61001, 5003, 23005, 79007}) {
    const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
    m.x[c] = 0.5 * (m.x[a] + m.x[b]);
    m.y[c] = 0.5 * (m.y[a] + m.y[b]);
    m.z[c] = 1e-8 * h;
  }
  const std::vector<int32_t> want = oracle_needles(m);
  REQUIRE(want.size() >= 4);
  for (int threads : {1, 2, 4}) {
    CAPTURE(threads);
    tbb::task_arena arena(threads);
    MeshDefects d;
    arena.execute([&] { d = detect_mesh_defects(m); });
    CHECK(d.needle_faces == static_cast<int64_t>(want.size()));
    CHECK(d.first_needle_face == want.front());
    CHECK(d.zero_area_faces == 0);
  }
}
