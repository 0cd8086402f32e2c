// Determinism of every pipeline (DESIGN.md "Pipelines and
// parallelism": the same input gives the same output whatever the thread count).
//
// Each case runs one pipeline three times — with 1 thread, with 2 threads, and
// with 2 threads again — and compares the raw bytes of everything it outputs
// (memcmp, no tolerance). A run executes inside a tbb::task_arena of that many
// threads and passes the same count in RunContext::threads, so both the
// kernels that open their own arena and those that use the caller's
// (parallel_for over vertices) see it. Seeds are fixed, so the repeated run
// also checks "same seed, same result". The engine Session (a facade over the
// pipelines, with caches) is checked the same way with a fresh Session per run.
// The meshes are small but large enough
// that the factorization has independent subtrees and the per-vertex loops
// split into several blocks.
#include <oneapi/tbb/task_arena.h>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/session.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/selected_inversion.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/laplacian/flipfree_param.hpp"
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/param/patch_param.hpp"
#include "locus/pipelines/laplacian/perfect_laplacian.hpp"
#include "locus/pipelines/laplacian/self_supporting.hpp"

using namespace locus;

namespace {

// The raw bytes of a pipeline's outputs, appended in a fixed order; `starts`
// records where each output begins, so a mismatch names the output (0-based).
struct Bytes {
  std::vector<unsigned char> data;
  std::vector<size_t> starts;
  template <class T>
  void add(std::span<const T> v) {
    starts.push_back(data.size());
    const uint64_t count = v.size();
    append(&count, sizeof count);
    append(v.data(), v.size() * sizeof(T));
  }
  template <class V>
  void add_vec(const V& v) {
    add(std::span<const typename V::value_type>(v.data(), v.size()));
  }
  template <class T>
  void add_value(T x) {
    starts.push_back(data.size());
    append(&x, sizeof x);
  }
  // Index of the output that holds byte `at`.
  size_t output_at(size_t at) const {
    return static_cast<size_t>(std::upper_bound(starts.begin(), starts.end(), at) - starts.begin()) - 1;
  }
  void add_mesh(const Mesh& m) {
    add_vec(m.x);
    add_vec(m.y);
    add_vec(m.z);
    add_vec(m.face_vertices);
  }
  void add_points(std::span<const SurfacePoint> pts) {
    for (const SurfacePoint& p : pts) {
      add_value(p.face);
      add_value(p.vertex);
      add_value(p.bary);
    }
  }

 private:
  void append(const void* p, size_t bytes) {
    const auto* c = static_cast<const unsigned char*>(p);
    data.insert(data.end(), c, c + bytes);
  }
};

// Runs `pipeline(ctx)` with 1, 2 and again 2 threads and requires identical bytes.
template <class Pipeline>
void check_deterministic(Pipeline&& pipeline) {
  std::vector<Bytes> runs;
  for (int threads : {1, 2, 2}) {
    tbb::task_arena arena(threads);
    RunContext ctx;
    ctx.threads = threads;
    Bytes out;
    arena.execute([&] { out = pipeline(ctx); });
    runs.push_back(std::move(out));
  }
  REQUIRE(!runs[0].data.empty());
  for (size_t k = 1; k < runs.size(); ++k) {
    INFO("run " << k << " (2 threads) against the 1-thread run");
    REQUIRE(runs[k].data.size() == runs[0].data.size());
    const bool same = std::memcmp(runs[k].data.data(), runs[0].data.data(), runs[0].data.size()) == 0;
    if (!same) {
      size_t at = 0;
      while (runs[k].data[at] == runs[0].data[at]) ++at;
      INFO("first difference in output " << runs[0].output_at(at) << " (byte " << at - runs[0].starts[runs[0].output_at(at)]
                                         << " of it)");
      CHECK(same);
    }
  }
}

std::vector<double> seeded_values(size_t n, uint64_t seed) {
  std::vector<double> v(n);
  uint64_t s = seed;
  for (double& x : v) {
    s += 0x9e3779b97f4a7c15ull;
    uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    x = static_cast<double>(z >> 11) * 0x1.0p-53 * 2.0 - 1.0;
  }
  return v;
}

NumericFactor factor_of(const CscMatrix& A, const RunContext& ctx) {
  return factorize(analyze(A, order_matrix(A)), A, ctx);
}

// A quad grid in space (a vault), for the polygon pipelines.
Mesh quad_vault(int n) {
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
  return m;
}

}  // namespace

TEST_CASE("determinism: ordering, symbolic analysis, factorization and full solves") {
  const Mesh m = make_random_sphere(3000, 11);
  const CscMatrix A = heat_operator(m, 0.01);
  const std::vector<double> b = seeded_values(A.ncols, 3), b8 = seeded_values(A.ncols * size_t(kLanes), 4);
  check_deterministic([&](const RunContext& ctx) {
    const NumericFactor F = factor_of(A, ctx);
    Bytes out;
    out.add_vec(F.symbolic->perm);
    out.add_vec(F.symbolic->super_first_col);
    out.add_vec(F.values);
    std::vector<double> x = b, x8 = b8;
    solve(F, x);
    solve8(F, x8);
    out.add_vec(x);
    out.add_vec(x8);
    NumericFactor G = F;  // refactorization with new values, same pattern
    refactorize(G, heat_operator(m, 0.1), ctx);
    out.add_vec(G.values);
    return out;
  });
}

TEST_CASE("determinism: local solves (subset and selective plans, 1 and 8 lanes) and selected inversion") {
  const Mesh m = make_random_sphere(3000, 12);
  const CscMatrix A = heat_operator(m, 0.01);
  check_deterministic([&](const RunContext& ctx) {
    const NumericFactor F = factor_of(A, ctx);
    Bytes out;
    const std::vector<int32_t> rhs{5, 17, 400}, wanted{1, 2, 3, 999, 2000, 2999};
    const SolvePlan exact = plan_subset_solve(*F.symbolic, rhs, wanted);
    const SolvePlan approx = plan_selective_solve(*F.symbolic, rhs, wanted);
    SolveWorkspace ws;
    std::vector<double> r1{1.0, -0.5, 2.0}, o1(wanted.size());
    solve_planned(F, exact, r1, o1, ws);
    out.add_vec(o1);
    solve_planned(F, approx, r1, o1, ws);
    out.add_vec(o1);
    const std::vector<double> r8 = seeded_values(rhs.size() * kLanes, 9);
    std::vector<double> o8(wanted.size() * kLanes);
    solve_planned8(F, exact, r8, o8, ws);
    out.add_vec(o8);
    const SelectedInverse Z = selected_inversion(F, ctx);
    out.add_vec(Z.values);
    out.add_vec(inverse_diagonal(Z));
    return out;
  });
}

TEST_CASE("determinism: auto-diffusion and heat kernel signature (subset, selinv)") {
  const Mesh m = make_random_sphere(1500, 13);
  const std::vector<double> ts{0.001, 0.01, 0.1};
  check_deterministic([&](const RunContext& ctx) {
    const HeatFactors H = factor_heat_operators(m, ts, ctx);
    Bytes out;
    std::vector<double> hks(size_t(m.num_vertices()) * ts.size());
    heat_kernel_signature(H, {}, AdfMethod::Subset, hks, ctx);
    out.add_vec(hks);
    heat_kernel_signature(H, {}, AdfMethod::Selinv, hks, ctx);
    out.add_vec(hks);
    std::vector<double> adf(3);
    auto_diffusion(H.factors[1], std::vector<int32_t>{0, 700, 1499}, AdfMethod::Full, adf, ctx);
    out.add_vec(adf);
    return out;
  });
}

TEST_CASE("determinism: pairwise heat exchange (subset, union, full)") {
  const Mesh m = make_random_sphere(2000, 14);
  const CscMatrix A = heat_operator(m, 0.005);
  check_deterministic([&](const RunContext& ctx) {
    const NumericFactor F = factor_of(A, ctx);
    Bytes out;
    HeatWorkspace ws;
    const std::vector<int32_t> S{0, 10, 10, 300}, T{1, 2, 1500, 1999};
    std::vector<double> x(T.size());
    for (HeatExchangeMethod meth : {HeatExchangeMethod::Subset, HeatExchangeMethod::Union, HeatExchangeMethod::Full}) {
      heat_exchange(F, S, T, meth, x, ws);
      out.add_vec(x);
    }
    return out;
  });
}

TEST_CASE("determinism: harmonic patch parameterization from the global factor") {
  const Mesh m = make_random_sphere(2000, 15);
  const CscMatrix K = regularized_laplacian(m);
  const PatchGrower g = prepare_patch_grower(m);
  check_deterministic([&](const RunContext& ctx) {
    const NumericFactor F = factor_of(K, ctx);
    Bytes out;
    PatchWorkspace pws;
    SolveWorkspace ws;
    for (int32_t center : {0, 777}) {
      const PatchParam P = parameterize_patch(F, g, center, 200, pws, ws);
      out.add_vec(P.patch.vertices);
      out.add_vec(P.uv_raw);
      out.add_vec(P.uv);
    }
    return out;
  });
}

TEST_CASE("determinism: factor-once update and ROI deformation (laplacian, bilaplacian)") {
  const Mesh m = make_random_sphere(2000, 16);
  const Adjacency adj = vertex_adjacency(m);
  const CscMatrix A = regularized_laplacian(m);
  check_deterministic([&](const RunContext& ctx) {
    Bytes out;
    const NumericFactor L = factor_of(A, ctx);
    std::vector<int32_t> I;
    for (int32_t v = 0; v < m.num_vertices(); v += 3) I.push_back(v);
    const FactorUpdate U = update_factor(L, A, I, ctx);
    out.add_vec(U.factor.values);
    out.add_vec(U.factor.symbolic->perm);
    const FactorUpdate U2 = update_factor(U.factor, U.A_sub, std::vector<int32_t>{0, 1, 2, 5, 8, 13, 100, 200}, ctx);
    out.add_vec(U2.factor.values);
    for (DeformEnergy e : {DeformEnergy::Laplacian, DeformEnergy::Bilaplacian}) {
      const DeformOperator op = prepare_deform_operator(m, e, 1e-6, ctx);
      const DeformRegion region = make_deform_region(adj, 7, 0.2, 7, 2);
      const DeformSystem sys = prepare_deform_system(op, region, ctx);
      Mesh moved;
      const DeformSolveStats st = solve_deformation(sys.sub.factor, sys, m, handle_target(m, region, {0.1, 0.2, -0.3}), moved);
      out.add_mesh(moved);
      out.add_value(st.refinement_steps);
      out.add_value(st.residual);
    }
    return out;
  });
}

TEST_CASE("determinism: heat Voronoi (full and localized), diagram, heat centroids") {
  const Mesh m = make_random_sphere(1500, 17);
  const std::vector<SurfacePoint> sites = random_surface_points(m, 21, 5);
  // Localized neighborhoods: a Dijkstra disk of 300 vertices around a corner of each site's face.
  const DemLogMap dem(m);
  std::vector<std::vector<int32_t>> hoods(sites.size());
  {
    DemWorkspace dws;
    std::vector<int32_t> patch(300);
    for (size_t s = 0; s < sites.size(); ++s) {
      const int32_t v = sites[s].face >= 0 ? m.f0[sites[s].face] : sites[s].vertex;
      const int32_t k = dem.query(v, 300, std::numeric_limits<double>::infinity(), patch, {}, {}, dws);
      hoods[s].assign(patch.begin(), patch.begin() + k);
      std::sort(hoods[s].begin(), hoods[s].end());
    }
  }
  const CentroidGeometry geo = prepare_centroid_geometry(m);
  check_deterministic([&](const RunContext& ctx) {
    Bytes out;
    const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, 0.0, ctx);
    out.add_vec(H.factor.values);
    const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, ctx);
    out.add_vec(V.label);
    out.add_vec(V.top_site);
    out.add_vec(V.top_value);
    const VoronoiDiagram D = extract_voronoi_diagram(H, m, sites, V, ctx);
    out.add_vec(D.points);
    out.add_vec(D.segments);
    for (const auto& p : D.polylines) out.add_vec(p);
    const HeatVoronoi W = heat_voronoi(H, m, sites, hoods, {}, ctx);
    out.add_vec(W.label);
    out.add_vec(W.top_value);
    out.add_value(W.unreached);
    for (int32_t cell = 0; cell < 5; ++cell) {
      std::vector<int32_t> members;
      for (int32_t v = 0; v < m.num_vertices(); ++v)
        if (V.label[v] == cell) members.push_back(v);
      if (members.empty()) continue;
      const HeatCentroid c = heat_centroid(H, m, geo, members, true);
      out.add_points(std::span<const SurfacePoint>(&c.point, 1));
      out.add_value(c.hottest);
    }
    return out;
  });
}

TEST_CASE("determinism: CVT by Lloyd (localized, full, anisotropic)") {
  const Mesh m = make_random_sphere(1200, 18);
  LloydOptions base;
  base.sites = 24;
  base.iterations = 3;
  base.seed = 9;
  for (int variant = 0; variant < 3; ++variant) {
    LloydOptions o = base;
    if (variant == 1) o.solver = LloydOptions::Solver::Full;
    if (variant == 2) o.anisotropy = 0.05;
    INFO("variant " << variant << " (0 local, 1 full, 2 anisotropic local)");
    check_deterministic([&](const RunContext& ctx) {
      const LloydResult R = cvt_lloyd(m, o, ctx);
      Bytes out;
      out.add_points(R.sites);
      out.add_vec(R.label);
      out.add_value(R.unreached);
      out.add_value(R.mean_kept_fraction);
      return out;
    });
  }
}

TEST_CASE("determinism: heat geodesic (full and localized) and heat log map") {
  const Mesh m = make_random_sphere(2000, 19);
  check_deterministic([&](const RunContext& ctx) {
    Bytes out;
    const HeatLogMap lm(m, {}, ctx);
    const HeatGeodesic& geo = lm.geodesic();
    out.add_vec(geo.heat_factor().values);
    out.add_vec(geo.poisson_factor().values);
    HeatGeodesicWorkspace gws;
    std::vector<double> full(m.num_vertices());
    geo.query_full(3, full, gws);
    out.add_vec(full);
    const DemLogMap dem(m);
    DemWorkspace dws;
    std::vector<int32_t> patch(150);
    patch.resize(dem.query(3, 150, std::numeric_limits<double>::infinity(), patch, {}, {}, dws));
    std::vector<double> d(patch.size()), a(patch.size()), u(patch.size()), v(patch.size());
    geo.query(3, patch, d, gws);
    out.add_vec(d);
    LogMapWorkspace lws;
    for (LogMapAngle ang : {LogMapAngle::Auto, LogMapAngle::LogHeat, LogMapAngle::LogHeatTwoRing, LogMapAngle::HeatAverage}) {
      lm.query(3, patch, {d, a, u, v}, lws, ang);
      out.add_vec(d);
      out.add_vec(a);
      out.add_vec(u);
      out.add_vec(v);
    }
    lm.query_full(3, patch, {d, a, u, v}, lws);
    out.add_vec(u);
    out.add_vec(v);
    return out;
  });
}

TEST_CASE("determinism: DEM log map") {
  const Mesh m = make_random_sphere(2000, 20);
  check_deterministic([&](const RunContext&) {
    Bytes out;
    const DemLogMap dem(m);
    DemWorkspace ws;
    std::vector<int32_t> patch(400);
    std::vector<double> u(400), v(400);
    for (int32_t c : {0, 1000}) {
      const int32_t k = dem.query(c, 400, std::numeric_limits<double>::infinity(), patch, u, v, ws);
      out.add_value(k);
      out.add_vec(patch);
      out.add_vec(u);
      out.add_vec(v);
    }
    return out;
  });
}

TEST_CASE("determinism: perfect Laplacian, flip-free parameterization, self-supporting surface") {
  const Mesh vault = quad_vault(8);
  Mesh noisy = make_icosphere(2);
  {
    const std::vector<double> r = seeded_values(noisy.x.size(), 21);
    for (size_t i = 0; i < noisy.x.size(); ++i) {
      const double s = 1 + 0.05 * r[i];
      noisy.x[i] *= s;
      noisy.y[i] *= s;
      noisy.z[i] *= s;
    }
  }
  const Mesh disk = make_disk(6, 0.3, 11);
  check_deterministic([&](const RunContext& ctx) {
    Bytes out;
    MeshPerfectLaplacianOptions po;
    po.iteration.max_iterations = 25;
    const MeshPerfectLaplacianResult P = perfect_laplacian(noisy, po, ctx);
    out.add_vec(P.run.weights);
    for (const auto& c : P.run.pos) out.add_vec(c);
    out.add_value(P.run.iterations);
    FlipFreeParamOptions fo;
    fo.iteration.max_iterations = 25;
    const FlipFreeParamResult F = flipfree_param(disk, fo, ctx);
    out.add_vec(F.uv);
    SelfSupportOptions so;
    so.iteration.max_iterations = 25;
    const SelfSupportResult S = self_supporting(vault, so, ctx);
    for (const auto& c : S.pos) out.add_vec(c);
    out.add_vec(S.forces);
    return out;
  });
}

TEST_CASE("determinism: engine Session (geodesic, log map, heat values, CVT, deformation)") {
  const Mesh m = make_random_sphere(1500, 22);
  check_deterministic([&](const RunContext& ctx) {
    const Session s{Mesh(m)};  // fresh caches: every factor is computed inside this run
    Bytes out;
    out.add_vec(s.geodesic_distance(4, {}, ctx));
    const LogMapResult lm = s.logmap(4, 0.1, {}, ctx);
    out.add_vec(lm.patch);
    out.add_vec(lm.u);
    out.add_vec(lm.v);
    out.add_vec(s.heat_values(std::vector<int32_t>{0, 9, 700}, std::vector<int32_t>{1, 2, 1400}, {}, ctx));
    const CvtResult c = s.cvt(12, 2, 5, ctx);
    out.add_vec(c.label);
    out.add_vec(c.site_xyz);
    DeformRequest req;
    req.roi_seed = 30;
    req.roi_fraction = 0.2;
    req.handle_vertex = 30;
    req.offset = {0.0, 0.1, 0.2};
    req.energy = DeformEnergyKind::Bilaplacian;
    out.add_vec(s.deform(req, ctx).xyz);
    return out;
  });
}
