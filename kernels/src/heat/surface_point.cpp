// Points on a triangle mesh (kernels/include/locus/kernels/heat/surface_point.hpp).
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

void check_surface_point(const Mesh& m, const SurfacePoint& p, const char* what, size_t index) {
  const std::string name = std::string(what) + " " + std::to_string(index);
  if (p.face < 0) {
    if (p.vertex < 0 || p.vertex >= m.num_vertices())
      fail(ErrorCode::BadUsage, name + " is vertex " + std::to_string(p.vertex) + ", but the mesh has " +
                                    std::to_string(m.num_vertices()) + " vertices");
    return;
  }
  if (p.face >= m.num_faces() || !m.is_triangle_mesh())
    fail(ErrorCode::BadUsage, name + " lies on face " + std::to_string(p.face) + ", but the mesh has " +
                                  std::to_string(m.num_faces()) + " triangles");
  double sum = 0;
  for (double b : p.bary) {
    if (!std::isfinite(b) || b < -1e-9)
      fail(ErrorCode::BadUsage, name + " has a barycentric weight that is negative or not finite");
    sum += b;
  }
  if (std::abs(sum - 1.0) > 1e-9) fail(ErrorCode::BadUsage, name + ": barycentric weights do not sum to 1");
}

std::array<double, 3> surface_point_position(const Mesh& m, const SurfacePoint& p) {
  if (p.face < 0) return {m.x[p.vertex], m.y[p.vertex], m.z[p.vertex]};
  const int32_t v[3] = {m.f0[p.face], m.f1[p.face], m.f2[p.face]};
  std::array<double, 3> r{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    r[0] += p.bary[k] * m.x[v[k]];
    r[1] += p.bary[k] * m.y[v[k]];
    r[2] += p.bary[k] * m.z[v[k]];
  }
  return r;
}

int surface_point_support(const Mesh& m, const SurfacePoint& p, int32_t v[3], double w[3]) {
  if (p.face < 0) {
    v[0] = p.vertex;
    w[0] = 1.0;
    return 1;
  }
  const int32_t fv[3] = {m.f0[p.face], m.f1[p.face], m.f2[p.face]};
  int c = 0;
  for (int k = 0; k < 3; ++k)
    if (p.bary[k] > 0) {
      v[c] = fv[k];
      w[c++] = p.bary[k];
    }
  if (c == 0) {  // all weights within rounding of zero: the point is the first corner
    v[0] = fv[0];
    w[0] = 1.0;
    c = 1;
  }
  return c;
}

std::vector<SurfacePoint> random_surface_points(const Mesh& m, int32_t count, uint64_t seed) {
  const int32_t nf = m.num_faces();
  if (count < 0) fail(ErrorCode::BadUsage, "random surface points: negative count");
  if (nf == 0 || !m.is_triangle_mesh()) fail(ErrorCode::BadInput, mesh_name(m) + ": random points need a triangle mesh");
  HostVector<double> cum(nf);
  double acc = 0;
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t a = m.f0[f], b = m.f1[f], c = m.f2[f];
    const double u[3] = {m.x[b] - m.x[a], m.y[b] - m.y[a], m.z[b] - m.z[a]};
    const double v[3] = {m.x[c] - m.x[a], m.y[c] - m.y[a], m.z[c] - m.z[a]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    acc += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    cum[f] = acc;
  }
  uint64_t state = seed;
  auto next = [&state]() {  // splitmix64, uniform in [0, 1)
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  std::vector<SurfacePoint> out(count);
  for (int32_t i = 0; i < count; ++i) {
    const double r = next() * acc;
    const int32_t f = std::min<int32_t>(nf - 1, static_cast<int32_t>(std::upper_bound(cum.begin(), cum.end(), r) - cum.begin()));
    double s = next(), t = next();
    if (s + t > 1) {  // fold the unit square onto the triangle
      s = 1 - s;
      t = 1 - t;
    }
    out[i] = SurfacePoint{f, -1, {1 - s - t, s, t}};
  }
  return out;
}

}  // namespace locus
