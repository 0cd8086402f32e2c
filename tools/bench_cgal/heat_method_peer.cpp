// `locus-bench-cgal MESH`: the heat method's precompute (thesis §6.2, the two
// factorizations of the heat geodesic distance) in locus against CGAL's
// Heat_method_3, on the same mesh in the same process.
//
// A separate program, not part of locus-bench or the default build: CGAL is a
// GPL peer (tests and benchmarks only) and its headers take a minute to compile.
// Built with `cmake --build build --target locus-bench-cgal` when Debian's
// libcgal-dev is installed; it uses only locus' public API (Session), as a host
// would.
//
// Per repeat, alternately (so drift in the machine's state hits both):
//   locus: Session(mesh) (checks the mesh) + prepare_heat() (operators,
//          ordering, symbolic and numeric factorization of both systems);
//          then one geodesic_distance(source): the first answer.
//   CGAL:  Surface_mesh_geodesic_distances_3(mesh) (operators, both
//          SimplicialLDLT factorizations); then add_source + estimate: its
//          first answer. The Surface_mesh is built outside the timing, from
//          the same arrays (locus' Session copies its mesh inside the timing).
// Both use t = h^2 with h the mean edge length (CGAL's fixed choice, computed
// the same way in its build(); locus' default is 4 h^2, so it
// is asked for h^2 here; t does not change the work). Prints one JSON object: medians, ratios locus / CGAL, threads,
// and how far the two distance fields are apart (the same method, so they
// should agree to discretization noise; a large gap would make the timing
// comparison meaningless).
#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "locus/session.hpp"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using HeatMethod = CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh>;
using Clock = std::chrono::steady_clock;
const locus::HeatQuery kSameT{1.0, 0.0};  // t = h^2, CGAL's

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

SurfaceMesh to_surface_mesh(const locus::Mesh& m) {
  SurfaceMesh sm;
  std::vector<VertexIndex> vs(m.x.size());
  for (size_t i = 0; i < vs.size(); ++i) vs[i] = sm.add_vertex(Kernel::Point_3(m.x[i], m.y[i], m.z[i]));
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    if (sm.add_face(vs[m.f0[f]], vs[m.f1[f]], vs[m.f2[f]]) == SurfaceMesh::null_face()) {
      std::fprintf(stderr, "locus-bench-cgal: CGAL's Surface_mesh refuses face %d (non-manifold here)\n", f);
      std::exit(1);
    }
  }
  return sm;
}

struct Samples {
  std::vector<double> locus_precompute, locus_first, cgal_precompute, cgal_first;
};

void usage() {
  std::fprintf(stderr,
               "usage: locus-bench-cgal MESH [--repeats N (default 5)] [--source V (default 0)]\n"
               "  Times the heat method's precompute and first answer in locus and CGAL Heat_method_3.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) { usage(); return 2; }
  std::string path = argv[1];
  int repeats = 5;
  int32_t source = 0;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeats" && i + 1 < argc) repeats = std::atoi(argv[++i]);
    else if (a == "--source" && i + 1 < argc) source = std::atoi(argv[++i]);
    else { usage(); return 2; }
  }
  if (repeats < 1) { std::fprintf(stderr, "locus-bench-cgal: --repeats must be >= 1\n"); return 2; }

  locus::Mesh mesh;
  try {
    mesh = locus::Session::from_file(path).mesh();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "locus-bench-cgal: %s\n", e.what());
    return 1;
  }
  if (source < 0 || source >= mesh.num_vertices()) {
    std::fprintf(stderr, "locus-bench-cgal: --source %d is not a vertex of %s (it has %d)\n", source, path.c_str(),
                 mesh.num_vertices());
    return 2;
  }
  SurfaceMesh sm = to_surface_mesh(mesh);
  auto dmap = sm.add_property_map<VertexIndex, double>("v:locus_bench_distance", 0.0).first;

  Samples s;
  std::vector<double> d_locus, d_cgal(mesh.x.size());
  for (int r = 0; r < repeats; ++r) {
    {
      locus::Mesh copy = mesh;
      const auto t0 = Clock::now();
      locus::Session session(std::move(copy));
      session.prepare_heat(kSameT);
      s.locus_precompute.push_back(seconds_since(t0));
      d_locus = session.geodesic_distance(source, kSameT);
      s.locus_first.push_back(seconds_since(t0));
    }
    {
      const auto t0 = Clock::now();
      HeatMethod hm(sm);
      s.cgal_precompute.push_back(seconds_since(t0));
      hm.add_source(VertexIndex(static_cast<SurfaceMesh::size_type>(source)));
      hm.estimate_geodesic_distances(dmap);
      s.cgal_first.push_back(seconds_since(t0));
      for (size_t i = 0; i < d_cgal.size(); ++i) d_cgal[i] = get(dmap, VertexIndex(static_cast<SurfaceMesh::size_type>(i)));
    }
  }

  // Agreement of the two fields, relative to the largest distance.
  double max_d = 0, sum_diff = 0, max_diff = 0;
  for (size_t i = 0; i < d_cgal.size(); ++i) {
    max_d = std::max(max_d, d_cgal[i]);
    const double diff = std::abs(d_locus[i] - d_cgal[i]);
    sum_diff += diff;
    max_diff = std::max(max_diff, diff);
  }
  const double h = locus::Session(locus::Mesh(mesh)).mean_edge_length();
  const double lp = median(s.locus_precompute), lf = median(s.locus_first);
  const double cp = median(s.cgal_precompute), cf = median(s.cgal_first);
  std::printf(
      "{\"mesh\": \"%s\", \"vertices\": %d, \"faces\": %d, \"repeats\": %d, \"source\": %d,\n"
      " \"locus_threads\": %u, \"cgal_threads\": 1, \"cgal_version\": \"%s\",\n"
      " \"t\": %.6g,\n"
      " \"locus_precompute_s\": %.6f, \"cgal_precompute_s\": %.6f, \"precompute_ratio\": %.4f,\n"
      " \"locus_first_answer_s\": %.6f, \"cgal_first_answer_s\": %.6f, \"first_answer_ratio\": %.4f,\n"
      " \"distance_mean_abs_diff_rel\": %.3e, \"distance_max_abs_diff_rel\": %.3e}\n",
      path.c_str(), mesh.num_vertices(), mesh.num_faces(), repeats, source, static_cast<unsigned>(tbb::this_task_arena::max_concurrency()),
      CGAL_VERSION_STR, h * h, lp, cp, lp / cp, lf, cf, lf / cf,
      sum_diff / static_cast<double>(d_cgal.size()) / max_d, max_diff / max_d);
  return 0;
}
