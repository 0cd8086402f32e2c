// EmbeddingSystem::solve is const and re-entrant: its scratch is the
// caller's workspace or local to the call, so several threads may solve with
// one factored system at once and get the results of sequential solves, bit
// for bit, with or without a workspace of their own.
#include <doctest/doctest.h>

#include <cstdint>
#include <thread>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/polygon_laplacian.hpp"

using namespace locus;

TEST_CASE("embedding system: concurrent solves equal sequential ones") {
  const Mesh m = make_grid(40, 0.3, 5);
  const int32_t nv = m.num_vertices();
  const Edges E = unique_edges(m);
  std::vector<double> w(E.e0.size());
  for (size_t e = 0; e < w.size(); ++e) w[e] = 0.5 + static_cast<double>((e * 7919) % 101) / 101.0;
  std::vector<uint8_t> fixed(static_cast<size_t>(nv), 0);
  for (const std::vector<int32_t>& loop : boundary_loops(m))
    for (const int32_t v : loop) fixed[v] = 1;
  EmbeddingSystem sys(nv, E.e0, E.e1, fixed);
  sys.factor(w);
  const EmbeddingSystem& csys = sys;

  // Four problems: different fixed positions and right-hand sides.
  std::vector<Coords> pos(4), rhs(4);
  for (int p = 0; p < 4; ++p) {
    pos[p] = Coords{std::vector<double>(m.x), std::vector<double>(m.y), std::vector<double>(m.z)};
    for (int k = 0; k < 3; ++k) {
      for (double& x : pos[p][k]) x *= 1.0 + 0.1 * p + 0.01 * k;
      rhs[p][k].assign(static_cast<size_t>(nv), 0.001 * (p + 1) * (k + 1));
    }
  }
  std::vector<Coords> ref(4);
  for (int p = 0; p < 4; ++p) csys.solve(3, pos[p], rhs[p], 0.8, ref[p]);

  for (int round = 0; round < 3; ++round) {
    std::vector<Coords> got(4), got_ws(4);
    std::vector<std::thread> threads;
    for (int p = 0; p < 4; ++p)
      threads.emplace_back([&, p] {
        csys.solve(3, pos[p], rhs[p], 0.8, got[p]);
        EmbeddingSolveWorkspace ws;  // reused across two solves of different problems
        csys.solve(3, pos[(p + 1) % 4], rhs[(p + 1) % 4], 0.8, got_ws[(p + 1) % 4], ws);
        Coords again;
        csys.solve(3, pos[(p + 1) % 4], rhs[(p + 1) % 4], 0.8, again, ws);
        CHECK(again == got_ws[(p + 1) % 4]);
      });
    for (std::thread& t : threads) t.join();
    for (int p = 0; p < 4; ++p) {
      CHECK(got[p] == ref[p]);
      CHECK(got_ws[p] == ref[p]);
    }
  }
}
