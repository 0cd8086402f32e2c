// analyze() alone, 1 and 2 threads alternating (docs/ordering.md
// "Parallel symbolic analysis"): wall and process CPU time medians, and a
// digest of every array of the SymbolicFactor, so that two builds (before
// and after a change) can be compared for speed and for identical output.
//
//   cmake --build build --target locus-bench-symbolic
//   build/locus-bench-symbolic cache/meshes/armadillo.off 2 15 [auto|nd|amd]
//
// (mesh, 1:4 subdivisions, repeats, ordering). For a before/after pair,
// compile this file against the other commit's liblocus.a too (the include
// and link flags of build.ninja's locus-bench) and alternate the two.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/mesh_io.hpp"

using namespace locus;

namespace {

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

template <class V>
void mix(uint64_t& h, const V& v) {
  for (auto x : v) {
    h = (h ^ static_cast<uint64_t>(x)) * 1099511628211ull;
    h ^= h >> 29;
  }
}

uint64_t digest(const SymbolicFactor& S) {
  uint64_t h = 1469598103934665603ull;
  mix(h, S.perm);
  mix(h, S.iperm);
  mix(h, S.parent);
  mix(h, S.col_count);
  mix(h, S.super_first_col);
  mix(h, S.col_to_super);
  mix(h, S.super_parent);
  mix(h, S.super_row_ptr);
  mix(h, S.super_rows);
  mix(h, S.super_value_ptr);
  mix(h, S.a_super_ptr);
  mix(h, S.a_src);
  mix(h, S.a_dst);
  mix(h, S.update_ptr);
  mix(h, S.update_from);
  const std::vector<int64_t> scalars{S.nnz_exact, S.etree_height, S.ns, S.nnz_L, S.super_etree_height,
                                     static_cast<int64_t>(S.a_pattern_hash), S.a_nnz, S.max_update_entries,
                                     S.max_super_rows};
  mix(h, scalars);
  return h;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s mesh subdivisions repeats [auto|nd|amd]\n", argv[0]);
    return 2;
  }
  const int sub = std::atoi(argv[2]), reps = std::max(1, std::atoi(argv[3]));
  const std::string method = argc > 4 ? argv[4] : "auto";
  Mesh m = read_mesh(argv[1]);
  if (sub > 0) m = subdivide_midpoint(m, sub);
  const double h = mean_edge_length(m);
  const CscMatrix A = heat_operator(m, h * h);
  OrderingOptions oo;
  if (method == "nd") oo.method = OrderingOptions::Method::NestedDissection;
  if (method == "amd") oo.method = OrderingOptions::Method::Amd;
  const Ordering o = order_matrix(A, oo);
  std::vector<double> wall[2], cpu[2];
  uint64_t dig[2] = {0, 0};
  for (int r = 0; r < reps; ++r)
    for (int t = 1; t <= 2; ++t) {
      RunContext ctx;
      ctx.threads = t;
      const double c0 = cpu_seconds();
      const auto w0 = std::chrono::steady_clock::now();
      const auto S = analyze(A, o, {}, ctx);
      wall[t - 1].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
      cpu[t - 1].push_back(cpu_seconds() - c0);
      if (r == 0) dig[t - 1] = digest(*S);
    }
  std::printf("{\"n\": %d, \"ordering\": \"%s\", \"repeats\": %d, \"wall_1\": %.4f, \"cpu_1\": %.4f, \"wall_2\": %.4f, "
              "\"cpu_2\": %.4f, \"digest_1\": \"%016llx\", \"digest_2\": \"%016llx\"}\n",
              A.ncols, method.c_str(), reps, median(wall[0]), median(cpu[0]), median(wall[1]), median(cpu[1]),
              static_cast<unsigned long long>(dig[0]), static_cast<unsigned long long>(dig[1]));
  return dig[0] == dig[1] ? 0 : 1;
}
