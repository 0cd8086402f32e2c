// Analytic surfaces of the accuracy benchmarks and their exact distance and
// azimuth (analytic_surfaces.hpp).
#include "tools/bench/analytic_surfaces.hpp"

#include <cmath>
#include <cstdlib>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"

namespace locus::bench {

Surface make_surface(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) fail(ErrorCode::BadUsage, "accuracy surface '" + spec + "': expected KIND:SIZE");
  const std::string kind = spec.substr(0, colon);
  char* end = nullptr;
  const long size = std::strtol(spec.c_str() + colon + 1, &end, 10);
  if (*end != '\0' || size < 1) fail(ErrorCode::BadUsage, "accuracy surface '" + spec + "': bad size");
  Surface s;
  if (kind == "icosphere") {
    if (size > 9) fail(ErrorCode::BadUsage, "icosphere level at most 9");
    s.mesh = make_icosphere(static_cast<int>(size), 1.0);
    s.kind = "sphere";
  } else if (kind == "random-sphere") {
    s.mesh = make_random_sphere(static_cast<int32_t>(size), 12345);
    s.kind = "sphere";
  } else if (kind == "cube-sphere" || kind == "cube-sphere-tri") {
    if (size > 2000) fail(ErrorCode::BadUsage, "cube-sphere: at most 2000 quads per cube edge");
    s.mesh = make_cube_sphere(static_cast<int32_t>(size), kind == "cube-sphere-tri");
    s.kind = "sphere";
  } else if (kind == "bump") {
    s.mesh = make_disk(static_cast<int32_t>(size));
    s.kind = "bump";
    const double R = 1.5, sig2 = s.sigma * s.sigma;
    for (int32_t i = 0; i < s.mesh.num_vertices(); ++i) {
      s.mesh.x[i] *= R;
      s.mesh.y[i] *= R;
      s.mesh.z[i] = std::exp(-(s.mesh.x[i] * s.mesh.x[i] + s.mesh.y[i] * s.mesh.y[i]) / sig2);
    }
    // s(r) = int_0^r sqrt(1 + f'(p)^2) dp, f' = -2p/sigma^2 exp(-p^2/sigma^2); Simpson per cell.
    const int cells = 200000;
    const double step = 2.2 / cells;
    auto integrand = [&](double p) {
      const double fp = -2 * p / sig2 * std::exp(-p * p / sig2);
      return std::sqrt(1 + fp * fp);
    };
    s.profile_r.resize(cells + 1);
    s.profile_s.resize(cells + 1);
    for (int k = 0; k <= cells; ++k) s.profile_r[k] = k * step;
    for (int k = 0; k < cells; ++k) {
      const double a = k * step;
      s.profile_s[k + 1] =
          s.profile_s[k] + step / 6 * (integrand(a) + 4 * integrand(a + step / 2) + integrand(a + step));
    }
  } else {
    fail(ErrorCode::BadUsage, "accuracy surface kind '" + kind + "': use icosphere, random-sphere, cube-sphere, cube-sphere-tri or bump");
  }
  return s;
}

double exact_angle(const Surface& s, int32_t c, int32_t j) {
  const Mesh& m = s.mesh;
  if (s.kind == "bump") return std::atan2(m.y[j] - m.y[c], m.x[j] - m.x[c]);
  const double n[3] = {m.x[c], m.y[c], m.z[c]};
  const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double nn[3] = {n[0] / nl, n[1] / nl, n[2] / nl};
  // Any tangent basis: the rotation is removed by the best global offset.
  double a[3] = {1, 0, 0};
  if (std::abs(nn[0]) > 0.9) a[0] = 0, a[1] = 1;
  const double an = a[0] * nn[0] + a[1] * nn[1] + a[2] * nn[2];
  double b1[3] = {a[0] - an * nn[0], a[1] - an * nn[1], a[2] - an * nn[2]};
  const double bl = std::sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  for (double& x : b1) x /= bl;
  const double b2[3] = {nn[1] * b1[2] - nn[2] * b1[1], nn[2] * b1[0] - nn[0] * b1[2], nn[0] * b1[1] - nn[1] * b1[0]};
  const double p[3] = {m.x[j], m.y[j], m.z[j]};
  return std::atan2(p[0] * b2[0] + p[1] * b2[1] + p[2] * b2[2], p[0] * b1[0] + p[1] * b1[1] + p[2] * b1[2]);
}

}  // namespace locus::bench
