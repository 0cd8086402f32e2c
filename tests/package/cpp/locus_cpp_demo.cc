// A C++ program using the public headers of the installed package
// (locus/session.hpp, locus/mesh.hpp, locus/error.hpp): a unit sphere built
// through the Mesh API, geodesic distances against great circles, symmetric
// heat values, the same answers from two threads, errors as locus::Error, and
// with a mesh path argument a Session read from that file; with
// LOCUS_PACKAGE_REFS set (make_references.cmake) also every pipeline of the
// Session, compared with the CLI's outputs for the same arguments. Exit 0 when every
// check passes.
#include <locus/error.hpp>
#include <locus/session.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
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

// ==== Every pipeline of the C++ Session against the CLI
// (tests/package/make_references.cmake wrote the CLI's outputs for the same
// arguments into $LOCUS_PACKAGE_REFS). C++17: no span, no designated initializers. ====

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    std::fprintf(stderr, "FAILED: cannot open %s\n", path.c_str());
    ++failures;
    return {};
  }
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

// The numbers of the JSON value of "key" (a number or nested arrays of numbers), flattened.
std::vector<double> json_numbers(const std::string& text, const std::string& key) {
  std::vector<double> out;
  size_t p = text.find("\"" + key + "\":");
  if (p == std::string::npos) return out;
  p += key.size() + 3;
  int depth = 0;
  while (p < text.size()) {
    const char c = text[p];
    if (c == ' ' || c == '\n' || c == ',') {
      ++p;
    } else if (c == '[') {
      ++depth;
      ++p;
    } else if (c == ']') {
      ++p;
      if (--depth == 0) break;
    } else {
      char* end = nullptr;
      out.push_back(std::strtod(text.c_str() + p, &end));
      p = static_cast<size_t>(end - text.c_str());
      if (depth == 0) break;
    }
  }
  return out;
}

// The leading double vertex properties (x y z, then the results) of a binary
// little-endian PLY written by locus, row-major; later int properties (the
// `valid` mask) are skipped by their size.
std::vector<double> ply_vertex_doubles(const std::string& path, int& props) {
  std::ifstream f(path, std::ios::binary);
  std::string line;
  int64_t nv = 0;
  int ints = 0;
  bool in_vertex = false;
  props = 0;
  while (std::getline(f, line)) {
    if (line.rfind("element vertex ", 0) == 0) {
      nv = std::stoll(line.substr(15));
      in_vertex = true;
    } else if (line.rfind("element ", 0) == 0) {
      in_vertex = false;
    } else if (in_vertex && ints == 0 && line.rfind("property double ", 0) == 0) {
      ++props;
    } else if (in_vertex && line.rfind("property int ", 0) == 0) {
      ++ints;
    } else if (line.rfind("end_header", 0) == 0) {
      break;
    }
  }
  const size_t stride = sizeof(double) * static_cast<size_t>(props) + 4 * static_cast<size_t>(ints);
  std::vector<double> v(static_cast<size_t>(nv * props));
  std::vector<char> row(stride);
  for (int64_t i = 0; i < nv; ++i) {
    if (!f.read(row.data(), static_cast<std::streamsize>(stride))) return {};
    std::memcpy(v.data() + i * props, row.data(), sizeof(double) * static_cast<size_t>(props));
  }
  return v;
}

// The numbers of every OBJ line starting with `tag` ("v ", "vt ").
std::vector<double> obj_numbers(const std::string& path, const std::string& tag) {
  std::ifstream f(path);
  std::vector<double> out;
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(tag, 0) == 0) {
      std::istringstream is(line.substr(tag.size()));
      double x;
      while (is >> x) out.push_back(x);
    }
  return out;
}

void compare(const char* what, const std::vector<double>& a, const std::vector<double>& b, double tol) {
  double diff = a.size() == b.size() ? 0.0 : INFINITY, scale = 1e-300;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double d = std::abs(a[i] - b[i]);
    if (!(d <= diff)) diff = d;
    scale = std::max(scale, std::abs(b[i]));
  }
  std::printf("  %-34s %8zu values, max |api - cli| / max |cli| = %.3g\n", what, a.size(), diff / scale);
  if (a.empty() || !(diff / scale <= tol)) {
    std::fprintf(stderr, "FAILED: %s differs from the CLI (%zu vs %zu values, %.3g)\n", what, a.size(), b.size(),
                 diff / scale);
    ++failures;
  }
}

// Per-edge "v0 v1 value" text against edges (2 per edge) and values.
void compare_edges(const char* what, const std::string& path, const std::vector<int32_t>& edges,
                   const std::vector<double>& values) {
  std::ifstream f(path);
  std::vector<double> ref;
  int64_t a, b, wrong = 0;
  double w;
  while (f >> a >> b >> w) {
    const size_t e = ref.size();
    if (2 * e + 1 >= edges.size() || edges[2 * e] != a || edges[2 * e + 1] != b) ++wrong;
    ref.push_back(w);
  }
  expect(wrong == 0, "the CLI's edges are the Session's");
  compare(what, values, ref, 1e-9);
}

// The patch's uv against the OBJ's vt lines: per patch vertex k, vt line k.
void compare_patch(const char* what, const locus::PatchParamResult& r, const std::string& obj) {
  compare(what, r.uv, obj_numbers(obj, "vt "), 1e-9);
}

void cli_checks(const std::string& mesh, const std::string& dir) {
  const locus::Session s = locus::Session::from_file(mesh);
  const int32_t n = s.num_vertices();
  const std::vector<int32_t> ids{0, 1000, 5000, 9000, 13000, 20000};
  std::vector<locus::MeshPoint> sites;
  for (int32_t v : ids) sites.push_back(locus::MeshPoint::at_vertex(v));
  int props = 0;

  {
    const std::vector<locus::MeshPoint> one(1, locus::MeshPoint::at_vertex(0));
    const std::vector<double> d = s.geodesic_distance(one);
    const std::vector<double> ply = ply_vertex_doubles(dir + "/geodesic.ply", props);
    std::vector<double> ref;
    for (size_t i = 0; props == 4 && i < ply.size() / 4; ++i) ref.push_back(ply[4 * i + 3]);
    compare("geodesic (one source)", d, ref, 1e-12);
    const std::vector<double> multi = s.geodesic_distance_from_vertices(ids);
    double lo = INFINITY;
    for (int32_t v : ids) lo = std::min(lo, multi[v]);
    expect(lo == 0.0, "the nearest of 6 sources is at distance 0");
  }
  {
    const locus::VoronoiResult v = s.voronoi(sites);
    compare("voronoi points", v.points, obj_numbers(dir + "/voronoi.obj", "v "), 1e-12);
    const std::vector<double> lines = json_numbers(slurp(dir + "/voronoi.json"), "polylines");
    expect(lines.size() == 1 && lines[0] == static_cast<double>(v.line_offsets.size() - 1), "voronoi polyline count");
  }
  compare("voronoi points (50 random generators)", s.voronoi(s.random_points(50, 7)).points,
          obj_numbers(dir + "/voronoi_random.obj", "v "), 1e-12);
  compare("natural-neighbor coordinates",
          s.natural_neighbor_coordinates(sites, locus::MeshPoint::in_face(10, 0.2, 0.3, 0.5)).weight,
          json_numbers(slurp(dir + "/nncoords.json"), "weights"), 1e-12);
  const std::vector<int32_t> verts{0, 7, 12345};
  compare("auto-diffusion function", s.auto_diffusion(verts), json_numbers(slurp(dir + "/adf.json"), "adf"), 1e-12);
  std::vector<locus::HeatQuery> times;
  for (double tf : {1.0, 10.0, 100.0}) {
    locus::HeatQuery q;
    q.t_factor = tf;
    times.push_back(q);
  }
  compare("heat kernel signature", s.heat_kernel_signature(times, verts),
          json_numbers(slurp(dir + "/hks.json"), "hks"), 1e-12);
  compare("heat exchange", s.heat_exchange(std::vector<int32_t>{0, 1, 2}, std::vector<int32_t>{100, 200, 25000}),
          json_numbers(slurp(dir + "/heat.json"), "values"), 1e-12);
  {
    locus::DeformRequest r;
    r.roi_seed = 0;
    r.roi_fraction = 0.1;
    r.handle_vertex = 0;
    r.offset = {0.5, 1.0, 0.0};
    compare("deformation", s.deform(r).xyz, ply_vertex_doubles(dir + "/deform.ply", props), 1e-9);
  }
  locus::PatchParamRequest pr;
  pr.center = 0;
  pr.fraction = 0.1;
  compare_patch("patch parameterization (Neumann)", s.parameterize_patch(pr), dir + "/param_neumann.obj");
  pr.boundary = locus::PatchBoundary::Circle;
  compare_patch("patch parameterization (circle)", s.parameterize_patch(pr), dir + "/param_circle.obj");
  expect(s.stats().numeric_factorizations == 4, "one factor per t (3 heat operators) and one of -L + eps M served every query");

  // The chapter-2 pipelines and skinning weights on the disk cut from armadillo.
  const locus::Session p = locus::Session::from_file(dir + "/patch.obj");
  compare("disk parameterization (perfect)", p.parameterize_disk().uv, obj_numbers(dir + "/param_disk.obj", "vt "), 1e-9);
  {
    const std::vector<locus::MeshPoint> h{locus::MeshPoint::at_vertex(0), locus::MeshPoint::at_vertex(300),
                                          locus::MeshPoint::at_vertex(900)};
    const std::vector<double> ply = ply_vertex_doubles(dir + "/skinweights.ply", props);
    std::vector<double> ref;
    // The weights are the last three properties (the patch's UVs, read from patch.obj's vt, come first).
    const size_t np = static_cast<size_t>(props);
    for (size_t i = 0; np >= 6 && i < ply.size() / np; ++i)
      ref.insert(ref.end(), {ply[np * i + np - 3], ply[np * i + np - 2], ply[np * i + np - 1]});
    compare("skinning weights", p.skinning_weights(h).weight, ref, 1e-12);
  }
  locus::PerfectLaplacianRequest lr;
  lr.max_iterations = 20;
  const locus::PerfectLaplacianOutput pl = p.perfect_laplacian(lr);
  compare_edges("perfect Laplacian weights", dir + "/perfect_laplacian.obj.weights.txt", pl.edges, pl.weights);
  compare("perfect Laplacian embedding", pl.xyz, obj_numbers(dir + "/perfect_laplacian.obj", "v "), 1e-9);
  locus::SelfSupportRequest sr;
  sr.max_iterations = 20;
  const locus::SelfSupportOutput ss = p.self_supporting(sr);
  compare_edges("self-supporting forces", dir + "/selfsupport.obj.forces.txt", ss.edges, ss.forces);
  compare("self-supporting surface", ss.xyz, obj_numbers(dir + "/selfsupport.obj", "v "), 1e-9);
  (void)n;

  // The one-shot forms on a quad mesh (no Session; a Session on it gives the same, tests/engine/session_pipelines.cpp).
  const locus::Mesh quad = locus::read_mesh(dir + "/quad_grid.off");
  compare("disk parameterization (quads)", locus::parameterize_disk_of(quad).uv,
          obj_numbers(dir + "/param_quad.obj", "vt "), 1e-9);
  const locus::PerfectLaplacianOutput ql = locus::perfect_laplacian_of(quad, lr);
  compare_edges("perfect Laplacian weights (quads)", dir + "/perfect_laplacian_quad.obj.weights.txt", ql.edges, ql.weights);
  compare("perfect Laplacian embedding (quads)", ql.xyz, obj_numbers(dir + "/perfect_laplacian_quad.obj", "v "), 1e-9);
  const locus::SelfSupportOutput qs = locus::self_supporting_of(quad, sr);
  compare_edges("self-supporting forces (quads)", dir + "/selfsupport_quad.obj.forces.txt", qs.edges, qs.forces);
  compare("self-supporting surface (quads)", qs.xyz, obj_numbers(dir + "/selfsupport_quad.obj", "v "), 1e-9);
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
  if (argc > 1 && std::getenv("LOCUS_PACKAGE_REFS")) {
    std::printf("every pipeline against the CLI (%s):\n", std::getenv("LOCUS_PACKAGE_REFS"));
    try {
      cli_checks(argv[1], std::getenv("LOCUS_PACKAGE_REFS"));
    } catch (const locus::Error& e) {
      std::fprintf(stderr, "FAILED: %s\n", e.what());
      ++failures;
    }
  }
  if (failures) {
    std::fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  std::printf("all checks passed\n");
  return 0;
}
