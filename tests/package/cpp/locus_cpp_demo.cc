// A C++ program using the public headers of the installed package
// (locus/session.hpp, locus/mesh.hpp, locus/error.hpp): a unit sphere built
// through the Mesh API, geodesic distances against great circles, symmetric
// heat values, the same answers from two threads, errors as locus::Error, and
// with a mesh path argument a Session read from that file. Exit 0 when every
// check passes.
#include <locus/error.hpp>
#include <locus/session.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>
#include <utility>
#include <vector>

namespace {

int failures = 0;

void expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

// Icosahedron refined `levels` times (1:4), on the unit sphere.
locus::Mesh icosphere(int levels) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v{{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                                       {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  std::vector<std::array<int32_t, 3>> f{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                        {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                        {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                        {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  auto unit = [](std::array<double, 3> a) {
    const double r = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<double, 3>{a[0] / r, a[1] / r, a[2] / r};
  };
  for (auto& a : v) a = unit(a);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int32_t, int32_t>, int32_t> mid;
    auto midpoint = [&](int32_t a, int32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(unit({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return mid[key] = static_cast<int32_t>(v.size() - 1);
    };
    std::vector<std::array<int32_t, 3>> g;
    for (const auto& t : f) {
      const int32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      g.push_back({t[0], a, c});
      g.push_back({t[1], b, a});
      g.push_back({t[2], c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
  locus::Mesh m;
  for (const auto& a : v) m.add_vertex(a[0], a[1], a[2]);
  for (const auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  const locus::Mesh m = icosphere(4);
  const locus::Session s(m);
  const int32_t n = s.num_vertices();

  const std::vector<double> d = s.geodesic_distance(0);
  double err = 0;
  for (int32_t i = 0; i < n; ++i) {
    const double c = m.x[i] * m.x[0] + m.y[i] * m.y[0] + m.z[i] * m.z[0];
    err += std::abs(d[i] - std::acos(std::clamp(c, -1.0, 1.0)));
  }
  err /= n;
  std::printf("icosphere %d vertices: mean |geodesic - great circle| = %.4g\n", n, err);
  expect(err < 0.02, "geodesic distance close to great circles");

  const std::vector<int32_t> a{0, 10, 20}, b{5, 15, 25, 35};
  const std::vector<double> hab = s.heat_values(a, b), hba = s.heat_values(b, a);
  double asym = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t k = 0; k < b.size(); ++k)
      asym = std::max(asym, std::abs(hab[i * b.size() + k] - hba[k * a.size() + i]) / hab[i * b.size() + k]);
  std::printf("heat values: max relative asymmetry %.3g\n", asym);
  expect(asym < 1e-10, "heat values symmetric");

  std::vector<double> d1, d2;
  std::thread t1([&] { d1 = s.geodesic_distance(100); });
  std::thread t2([&] { d2 = s.geodesic_distance(100); });
  t1.join();
  t2.join();
  expect(d1 == d2 && d1 == s.geodesic_distance(100), "concurrent queries agree bit for bit");
  expect(s.stats().heat_engines == 1, "one factorization served every query");

  try {
    s.geodesic_distance(n);
    expect(false, "an out-of-range source throws");
  } catch (const locus::Error& e) {
    expect(e.code() == locus::ErrorCode::BadUsage, "out-of-range source is BadUsage");
  }

  if (argc > 1) {
    const locus::Session f = locus::Session::from_file(argv[1]);
    const locus::LogMapResult r = f.logmap(0, 0.02);
    double rmax = 0;
    for (size_t k = 0; k < r.patch.size(); ++k) rmax = std::max(rmax, std::hypot(r.u[k], r.v[k]));
    std::printf("%s: %d vertices, log map of %zu vertices, radius %.4g\n", argv[1], f.num_vertices(),
                r.patch.size(), rmax);
    expect(!r.patch.empty() && rmax > 0 && std::isfinite(rmax), "log map on the file");
  }
  if (failures) {
    std::fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  std::printf("all checks passed\n");
  return 0;
}
