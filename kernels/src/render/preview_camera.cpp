// Preview camera from principal axes (kernels/include/locus/kernels/render/preview_camera.hpp).
#include "locus/kernels/render/preview_camera.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace locus {

namespace {

Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3d add(const Vec3d& a, const Vec3d& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3d mul(const Vec3d& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3d& a) { return std::sqrt(dot(a, a)); }
Vec3d unit(const Vec3d& a) {
  const double l = norm(a);
  return l > 0 ? mul(a, 1 / l) : Vec3d{0, 0, 0};
}

struct SurfaceMoments {
  Vec3d centre{0, 0, 0};
  std::array<Vec3d, 3> cov{};
  Vec3d area_vector{0, 0, 0};  // sum of face area vectors
  double area = 0;
};

// Fan triangles of every face; faces with invalid ids or non-finite corners are skipped.
template <class F>
void for_each_triangle(const Mesh& m, F&& f) {
  const int32_t nv = m.num_vertices();
  for (int32_t fi = 0; fi < m.num_faces(); ++fi) {
    const auto fv = m.face(fi);
    bool ok = fv.size() >= 3;
    for (int32_t v : fv) ok = ok && v >= 0 && v < nv && std::isfinite(m.x[v] + m.y[v] + m.z[v]);
    if (!ok) continue;
    const Vec3d a{m.x[fv[0]], m.y[fv[0]], m.z[fv[0]]};
    for (size_t k = 1; k + 1 < fv.size(); ++k)
      f(a, Vec3d{m.x[fv[k]], m.y[fv[k]], m.z[fv[k]]}, Vec3d{m.x[fv[k + 1]], m.y[fv[k + 1]], m.z[fv[k + 1]]});
  }
}

SurfaceMoments surface_moments(const Mesh& m) {
  SurfaceMoments s;
  // Shift by a vertex first so that far-off meshes do not lose digits.
  Vec3d origin{0, 0, 0};
  for (int32_t v = 0; v < m.num_vertices(); ++v)
    if (std::isfinite(m.x[v] + m.y[v] + m.z[v])) {
      origin = {m.x[v], m.y[v], m.z[v]};
      break;
    }
  Vec3d sum{0, 0, 0};
  std::array<Vec3d, 3> second{};
  for_each_triangle(m, [&](const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d n = mul(cross(sub(b, a), sub(c, a)), 0.5);
    const double w = norm(n);
    if (!std::isfinite(w)) return;
    s.area_vector = add(s.area_vector, n);
    s.area += w;
    const Vec3d g = sub(mul(add(add(a, b), c), 1.0 / 3), origin);
    sum = add(sum, mul(g, w));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) second[i][j] += w * g[i] * g[j];
  });
  if (!(s.area > 0)) {
    s.centre = origin;
    return s;
  }
  const Vec3d mean = mul(sum, 1 / s.area);
  s.centre = add(origin, mean);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.cov[i][j] = second[i][j] / s.area - mean[i] * mean[j];
  return s;
}

// How strongly an axis follows the file's y or z axis, and which.
double vertical_score(const Vec3d& e) { return std::max(std::abs(e[1]), std::abs(e[2])); }
bool z_dominant(const Vec3d& e) { return std::abs(e[2]) > std::abs(e[1]) + 1e-9; }

// Rotates v about the unit axis k by angle a (Rodrigues).
Vec3d rotate(const Vec3d& v, const Vec3d& k, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
}

}  // namespace

SymmetricEigen3 symmetric_eigen3(const std::array<Vec3d, 3>& a_in) {
  std::array<Vec3d, 3> a = a_in;
  std::array<Vec3d, 3> v{Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, 0, 1}};  // columns are eigenvectors
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (!(off > 1e-30 * diag)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- J^T A
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::array<int, 3> order{0, 1, 2};
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return a[i][i] > a[j][j]; });
  SymmetricEigen3 r;
  for (int k = 0; k < 3; ++k) {
    r.values[k] = a[order[k]][order[k]];
    r.vectors[k] = unit(Vec3d{v[0][order[k]], v[1][order[k]], v[2][order[k]]});
  }
  return r;
}

PreviewCamera principal_axes_camera(const Mesh& m, const std::optional<Vec3d>& view) {
  const SurfaceMoments s = surface_moments(m);
  PreviewCamera cam;
  cam.centre = s.centre;
  const SymmetricEigen3 eig = symmetric_eigen3(s.cov);
  Vec3d e[3] = {eig.vectors[0], eig.vectors[1], eig.vectors[2]};
  if (!(s.area > 0)) e[0] = {0, 1, 0}, e[1] = {1, 0, 0}, e[2] = {0, 0, 1};

  // Up: e1 or e2, whichever follows y or z more closely (y on a tie), pointing along +y / +z.
  const int iu = vertical_score(e[1]) > vertical_score(e[0]) + 1e-6 ? 1 : 0;
  Vec3d up = e[iu];
  const bool z_up = z_dominant(up);
  if ((z_up ? up[2] : up[1]) < 0) up = mul(up, -1);

  const Vec3d front = z_up ? Vec3d{0, 1, 0} : Vec3d{0, 0, -1};  // the side a figure faces, by convention
  // An open surface whose normals mostly agree (a terrain, a disk) is seen
  // like a landscape: its mean normal is "up", the camera raised above it.
  cam.one_sided = s.area > 0 && norm(s.area_vector) / s.area > 0.5;
  Vec3d back;
  if (cam.one_sided) {
    up = unit(s.area_vector);
    Vec3d level = sub(front, mul(up, dot(front, up)));
    if (norm(level) < 0.2) level = sub(e[0], mul(up, dot(e[0], up)));
    back = unit(level);
  } else {
    back = e[2];
    const double along = dot(back, front);
    if (along < -1e-6 || (std::abs(along) <= 1e-6 && back[0] < 0)) back = mul(back, -1);
  }
  if (view) {
    back = unit(*view);
    if (!(norm(back) > 0)) back = front;
  }
  // "up" must not be parallel to the looking direction: fall back to the next principal axis.
  Vec3d up_perp = sub(up, mul(back, dot(up, back)));
  if (norm(up_perp) < 0.2) {
    const Vec3d other = e[iu == 0 ? 1 : 0];
    up_perp = sub(other, mul(back, dot(other, back)));
    if (norm(up_perp) < 0.2) up_perp = sub(e[2], mul(back, dot(e[2], back)));
  }
  up = unit(up_perp);
  if (!view) {
    // Three-quarter view: turn about up, then raise the camera towards up.
    back = unit(rotate(back, up, 30.0 * M_PI / 180));
    const Vec3d side = unit(cross(up, back));
    back = unit(rotate(back, side, -(cam.one_sided ? 40.0 : 20.0) * M_PI / 180));
    up = unit(sub(up, mul(back, dot(up, back))));
  }
  cam.back = back;
  cam.up = up;
  cam.right = unit(cross(up, back));
  return cam;
}

}  // namespace locus
