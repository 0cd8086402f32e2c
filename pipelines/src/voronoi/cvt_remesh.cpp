// CVT remeshing: Lloyd, restricted dual, repair by added sites and, where the
// input's vertices are too coarse for the cells, by subdividing it
// (pipelines/include/locus/pipelines/voronoi/cvt_remesh.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include "locus/error.hpp"
#include "remesh_assembly.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/pipelines/voronoi/remesh_features.hpp"
#include "locus/pipelines/voronoi/remesh_refinement.hpp"
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"

namespace locus {

namespace {

// One repair round without relaxation: the sites beyond r's are new; only they
// are solved (on Dijkstra balls of 2.5 expected cell radii, as the relaxing
// rounds' first neighborhoods) and merged into r's diagram.
void add_sites(const Mesh& m, const MeshDerived& d, const HeatDiffusion& H, std::vector<SurfacePoint> sites,
               const RunContext& ctx, LloydResult& r) {
  const int32_t first = static_cast<int32_t>(r.sites.size());
  const int32_t ns = static_cast<int32_t>(sites.size());
  const double area = std::accumulate(d.mass.begin(), d.mass.end(), 0.0);
  const double radius = 2.5 * std::sqrt(area / (M_PI * ns));
  const std::span<const SurfacePoint> fresh(sites.data() + first, static_cast<size_t>(ns - first));
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  std::vector<std::vector<int32_t>> nb;
  run_with_threads(std::max(1, threads), [&] { nb = geodesic_neighborhoods(m, d.adjacency, fresh, radius, ctx); });
  heat_voronoi_add(H, m, sites, first, nb, {}, r.voronoi, ctx);
  r.sites = std::move(sites);
  r.label.assign(r.voronoi.label.begin(), r.voronoi.label.end());
}

// The mesh the cells live on: the input, or its midpoint subdivision (same
// surface, finer vertices), with its own operator when isotropic.
struct Level {
  const Mesh* m = nullptr;
  const MeshDerived* d = nullptr;
  LloydOptions lo;  // lo.prepared: this level's operator (null: cvt_lloyd factors)
  DualTopology topo;
};

// Repair rounds on one level: while defects are left and rounds remain, one
// site at each repair vertex (the new cells added to the last diagram, or Lloyd
// relaxing all sites), then the defects again. Stops early when no defect has
// a repair vertex left (every candidate holds a site: the cells are too coarse).
RestrictedDual repair_rounds(const Level& L, const RemeshOptions& o, bool incremental, RestrictedDual dual,
                             double p0, double p1, const RunContext& ctx, BatchStopwatch& sw, RemeshResult& r) {
  const double share = (p1 - p0) / std::max(1, o.max_repair_rounds);
  // Past max_repair_rounds (incremental rounds only, up to 4 times as many)
  // while the defects still fall: three rounds ago there were more.
  std::vector<int64_t> left{dual.defects.total()};
  auto go_on = [&](int round) {
    if (round < o.max_repair_rounds) return true;
    const size_t k = left.size();
    return incremental && round < 4 * o.max_repair_rounds && k > 3 && left[k - 1] < left[k - 4];
  };
  for (int round = 0; go_on(round) && dual.defects.total() > 0; ++round) {
    ctx.check_cancel();
    if (dual.repair_vertices.empty()) break;
    std::vector<SurfacePoint> sites = r.lloyd.sites;
    for (int32_t v : dual.repair_vertices) sites.push_back(vertex_point(v));
    r.added_sites += static_cast<int32_t>(dual.repair_vertices.size());
    const double q = std::min(round, o.max_repair_rounds - 1) * share;  // the extra rounds report no progress
    const RunContext part = ctx.sub(p0 + q, p0 + q + (round < o.max_repair_rounds ? share : 0));
    if (incremental) {
      add_sites(*L.m, *L.d, *L.lo.prepared, std::move(sites), part, r.lloyd);
    } else {
      LloydOptions ro = L.lo;
      // The last rounds only relabel: relaxation could open new defects elsewhere.
      ro.iterations = round + 2 < o.max_repair_rounds ? o.relax_iterations : 0;
      // The sites are spread already: first neighborhoods of 2.5 expected cell
      // radii (not 4) hold every cell and its neighbors (1.5 left vertices
      // unreached on armadillo at 5,000 sites).
      ro.init_radius = std::min(L.lo.init_radius, 2.5);
      r.lloyd = cvt_lloyd(*L.m, *L.d, std::move(sites), ro, part);
      r.lloyd_iterations += static_cast<int32_t>(r.lloyd.iter_s.size());
    }
    ++r.repair_rounds;
    r.repair_s += sw.lap();
    dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
    r.dual_s += sw.lap();
    left.push_back(dual.defects.total());
  }
  return dual;
}

// The finer level below `coarse`: its subdivision, derived data and operator
// (kept alive in the deques).
struct Levels {
  std::deque<Mesh> meshes;
  std::deque<MeshDerived> derived;
  std::deque<HeatDiffusion> ops;
};
// same_t: the coarse level's absolute diffusion time (the same cells, resolved
// finer); else t in units of the finer h^2, as on an input that fine.
Level finer(const Level& coarse, bool same_t, Levels& keep, const RunContext& ctx, RemeshResult& r) {
  Level L;
  L.m = &keep.meshes.emplace_back(subdivide_midpoint(*coarse.m, 1));
  L.d = &keep.derived.emplace_back(derive_mesh(*L.m));
  L.lo = coarse.lo;
  L.lo.prepared = nullptr;
  if (same_t && coarse.lo.prepared) L.lo.t_abs = coarse.lo.prepared->t;
  if (coarse.lo.anisotropy == 0)
    L.lo.prepared = &keep.ops.emplace_back(prepare_heat_diffusion(*L.m, *L.d, L.lo.t_factor, L.lo.t_abs, ctx));
  L.topo = dual_topology(*L.m, L.d->incidence);
  ++r.refinements;
  return L;
}

// The sites moved, unchanged, onto the finer level and labelled there.
Level refine_level(const Level& coarse, bool incremental, Levels& keep, const RunContext& ctx, RemeshResult& r) {
  Level L = finer(coarse, true, keep, ctx, r);
  LloydOptions ro = L.lo;
  ro.iterations = 0;  // relabel only: the sites stay where the coarse level put them
  ro.init_radius = std::min(L.lo.init_radius, 2.5);
  ro.keep_voronoi = incremental;
  r.lloyd = cvt_lloyd(*L.m, *L.d, refine_surface_points(*coarse.m, r.lloyd.sites), ro, ctx);
  return L;
}

// The last resort when heat labels keep breaking the closed-ball property (CAD
// needles and fans make the heat's argmax jump across cells on every level):
// graph-geodesic labels of the same sites (one multi-source Dijkstra,
// site_neighborhoods.hpp). Such cells are connected and a site on a vertex keeps
// it, so added sites shrink the cells around the defects until, at worst, the
// dual is the (manifold) level mesh itself: the rounds end with a manifold dual.
RestrictedDual geodesic_repair(const Level& L, RestrictedDual dual, const RunContext& ctx, BatchStopwatch& sw,
                               RemeshResult& r) {
  auto relabel = [&] {
    HostVector<int32_t> g = geodesic_site_cells(*L.m, L.d->adjacency, r.lloyd.sites);
    // A component no site reaches (heat labels hide it: their fallback fills
    // unreached vertices) gets a site at its first vertex.
    std::vector<uint8_t> seeded(static_cast<size_t>(L.d->components), 0);
    bool unreached = false;
    for (int32_t v = 0; v < L.m->num_vertices(); ++v)
      if (g[v] < 0 && L.d->component[v] >= 0 && !seeded[L.d->component[v]]) {
        seeded[L.d->component[v]] = 1;
        r.lloyd.sites.push_back(vertex_point(v));
        ++r.added_sites;
        unreached = true;
      }
    if (unreached) g = geodesic_site_cells(*L.m, L.d->adjacency, r.lloyd.sites);
    r.lloyd.label.assign(g.begin(), g.end());
    r.lloyd.voronoi = HeatVoronoi{};  // the heat lists no longer match the labels
    r.repair_s += sw.lap();
    dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
    r.dual_s += sw.lap();
  };
  relabel();
  ++r.geodesic_rounds;
  for (int32_t round = 0; dual.defects.total() > 0 && !dual.repair_vertices.empty() &&
                          round < L.m->num_vertices();
       ++round) {
    ctx.check_cancel();
    for (int32_t v : dual.repair_vertices) r.lloyd.sites.push_back(vertex_point(v));
    r.added_sites += static_cast<int32_t>(dual.repair_vertices.size());
    ++r.repair_rounds;
    ++r.geodesic_rounds;
    relabel();
  }
  return dual;
}

// The last level's labels and sites as labels and sites of the input: its
// first n vertices are the input's (subdivision appends), the sites go up
// through the levels.
void back_to_input(const Mesh& m, const std::deque<Mesh>& meshes, LloydResult& l) {
  if (meshes.empty()) return;
  for (size_t k = meshes.size(); k-- > 0;)
    l.sites = coarsen_surface_points(k == 0 ? m : meshes[k - 1], meshes[k], l.sites);
  l.label.resize(static_cast<size_t>(m.num_vertices()));
  l.voronoi = HeatVoronoi{};  // the diagram of a finer mesh
}

// The repair of one partition on level L: heat rounds, then finer levels
// (within a budget of max(64 sites, 4 n) vertices: beyond it a level costs
// more than its defects); where heat labels still break the closed-ball
// property, graph-geodesic rounds from the sites and level it started with
// (the heat rounds' sites crowd where heat labels misbehave).
struct RepairStage {
  const Mesh& m;
  const RemeshOptions& o;
  bool incremental;
  Levels& keep;
  const RunContext& ctx;
  BatchStopwatch& sw;
  RemeshResult& r;
};

RestrictedDual repair(const RepairStage& st, Level& L, RestrictedDual dual, double p0, double p1) {
  RemeshResult& r = st.r;
  const std::vector<SurfacePoint> start_sites = r.lloyd.sites;
  const Level start_level = L;
  const int32_t start_refinements = r.refinements, start_added = r.added_sites;
  const int64_t start_defects = dual.defects.total();
  dual = repair_rounds(L, st.o, st.incremental, std::move(dual), p0, p1, st.ctx, st.sw, r);
  // Rounds that left more defects than they found: heat labels misbehave on
  // this input (needles); finer levels keep its triangles' shapes, so the
  // geodesic rounds come next (cheese: minutes of subdivided levels saved).
  const bool heat_fails = dual.defects.total() > start_defects;
  // Defects the input's vertices cannot resolve (every candidate vertex holds
  // a site, or the rounds ran out): the same sites on a subdivided input.
  const int64_t budget =
      std::max<int64_t>(64 * static_cast<int64_t>(r.lloyd.sites.size()), 4 * int64_t{st.m.num_vertices()});
  while (!heat_fails && r.refinements < st.o.max_refinements && dual.defects.total() > 0 &&
         4 * int64_t{L.m->num_vertices()} <= budget) {
    st.ctx.check_cancel();
    if (st.o.corners_needed) st.o.corners_needed();  // the subdivision reads m.face_vertices
    L = refine_level(L, st.incremental, st.keep, st.ctx.sub(p1, p1), r);
    r.repair_s += st.sw.lap();
    dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
    r.dual_s += st.sw.lap();
    dual = repair_rounds(L, st.o, st.incremental, std::move(dual), p1, p1, st.ctx, st.sw, r);
  }
  if (dual.defects.total() == 0 || st.o.max_repair_rounds == 0) return dual;
  while (r.refinements > start_refinements) {
    st.keep.meshes.pop_back();
    st.keep.derived.pop_back();
    if (st.keep.ops.size() > st.keep.meshes.size()) st.keep.ops.pop_back();
    --r.refinements;
  }
  L = start_level;
  r.lloyd.sites = start_sites;
  r.added_sites = start_added;
  if (st.o.corners_needed) st.o.corners_needed();  // (RemeshOptions::corners_needed)
  return geodesic_repair(L, std::move(dual), st.ctx, st.sw, r);
}

// The sites of a density pass. excess > 0: drop `excess` sites, the smallest
// cells first, none on the boundary or in a component of four cells or fewer, none added by a repair or next to one
// (the topology needed them there; freeing the neighbors too made the repair
// add more than went on elephant-with-holes), no two neighbors; excess < 0: split the
// -excess largest cells (a site at the cell's vertex farthest from its
// site). Sites of empty cells go either way. `added` follows the sites.
int32_t adjust_sites(const Level& L, const RestrictedDual& dual, std::span<const int32_t> label, int32_t excess,
                     std::vector<SurfacePoint>& sites, std::vector<uint8_t>& added) {
  const int32_t ns = static_cast<int32_t>(sites.size()), n = L.m->num_vertices();
  std::vector<double> area(ns, 0.0);
  std::vector<int32_t> comp(ns, -1), comp_cells(static_cast<size_t>(L.d->components), 0);
  for (int32_t v = 0; v < n; ++v) {
    area[label[v]] += L.d->mass[v];
    if (comp[label[v]] < 0 && L.d->component[v] >= 0) ++comp_cells[comp[label[v]] = L.d->component[v]];
  }
  std::vector<std::vector<int32_t>> nb(ns);
  for (const auto& t : dual.triangles)
    for (int k = 0; k < 3; ++k) nb[t[k]].push_back(t[(k + 1) % 3]);
  std::vector<uint8_t> blocked(ns, 0), pick(ns, 0);
  for (int32_t s = 0; s < ns; ++s) {
    // A component keeps four cells at least (the fewest a closed one's dual has).
    if (dual.cell_size[s] == 0 || (excess > 0 && comp[s] >= 0 && comp_cells[comp[s]] <= 4)) blocked[s] = 1;
    if (excess > 0 && (added[s] || dual.boundary_vertex[s] >= 0)) {
      blocked[s] = 1;
      for (int32_t t : nb[s]) blocked[t] = 1;
    }
  }
  std::vector<int32_t> order(ns);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int32_t a, int32_t b) { return excess > 0 ? area[a] < area[b] : area[a] > area[b]; });
  int32_t left = std::abs(excess);
  for (int32_t s : order) {
    if (left == 0) break;
    if (blocked[s]) continue;
    pick[s] = 1;
    --left;
    for (int32_t t : nb[s]) blocked[t] = 1;
  }
  std::vector<int32_t> far(ns, -1);
  std::vector<double> far_d(ns, -1.0);
  if (excess < 0)
    for (int32_t v = 0; v < n; ++v) {
      const int32_t s = label[v];
      if (!pick[s]) continue;
      const auto p = surface_point_position(*L.m, sites[s]);
      const double dx = L.m->x[v] - p[0], dy = L.m->y[v] - p[1], dz = L.m->z[v] - p[2];
      if (dx * dx + dy * dy + dz * dz > far_d[s]) far_d[s] = dx * dx + dy * dy + dz * dz, far[s] = v;
    }
  std::vector<SurfacePoint> out;
  std::vector<uint8_t> out_added;
  for (int32_t s = 0; s < ns; ++s) {
    if (dual.cell_size[s] == 0 || (excess > 0 && pick[s])) continue;
    out.push_back(sites[s]);
    out_added.push_back(added[s]);
  }
  for (int32_t s = 0; s < ns; ++s)
    if (far[s] >= 0) {
      out.push_back(vertex_point(far[s]));
      out_added.push_back(0);
    }
  const int32_t removed = ns - static_cast<int32_t>(out.size());  // net of the split cells' new sites
  sites = std::move(out);
  added = std::move(out_added);
  return removed;
}

// A density pass's Lloyd run gives the sites, their labels and cells; the
// first run's per-iteration record (energy, moves, timings: what the JSON
// reports of Lloyd) stays. Returns the run's iterations.
int32_t adopt_cells(LloydResult&& from, LloydResult& into) {
  into.sites = std::move(from.sites);
  into.label = std::move(from.label);
  into.voronoi = std::move(from.voronoi);
  into.cell_area = std::move(from.cell_area);
  return static_cast<int32_t>(from.iter_s.size());
}

// The requested density: the dual has one vertex per non-empty cell, so
// repair sites and empty cells move the count off the request. While it is
// more than 1.5% off (at most density_passes times), sites are dropped or split
// (adjust_sites), Lloyd relaxes them a few iterations and the partition is
// repaired again; the repair's sites stay where they were needed. The count
// before the repair follows the error of the last pass (the repair adds about
// as many sites each time), and the pass closest to the request is kept.
struct DensityState {
  LloydResult lloyd;
  RestrictedDual dual;
  Level L;
  int32_t refinements = 0, added_sites = 0, removed_sites = 0, error = 0;
};

int32_t cells_of(const RestrictedDual& dual) {
  return static_cast<int32_t>(std::count_if(dual.cell_size.begin(), dual.cell_size.end(), [](int32_t c) { return c > 0; }));
}

RestrictedDual meet_density(const RepairStage& st, Level& L, RestrictedDual dual, double p) {
  RemeshResult& r = st.r;
  const int32_t want = st.o.lloyd.sites;
  std::vector<uint8_t> added(r.lloyd.sites.size(), 0);
  for (size_t s = static_cast<size_t>(want); s < added.size(); ++s) added[s] = 1;
  int32_t pre = want;  // sites before the last repair
  std::optional<DensityState> best;
  for (int pass = 0; pass < st.o.density_passes && dual.defects.total() == 0; ++pass) {
    const int32_t got = cells_of(dual), error = got - want;
    if (std::abs(error) <= std::max(1, 3 * want / 200)) break;  // within 1.5%
    if (best && std::abs(error) >= std::abs(best->error)) break;  // the last pass did not help
    best = DensityState{r.lloyd, dual, L, r.refinements, r.added_sites, r.removed_sites, error};
    // A few percent off: the sites stay (relaxing them would open new defects
    // for the repair to fill, the count overshooting again), only the excess
    // goes or the deficit is split; the optimization evens out the vertices.
    const bool relax = std::abs(error) * 20 > want;
    // Every component keeps three sites at least (the fewest a dual of it has).
    pre = relax ? std::max(3 * L.d->components, pre - error) : want;
    const int32_t drop = got - pre;
    if ((error > 0) != (drop > 0)) break;  // no site left to drop
    if (st.o.corners_needed) st.o.corners_needed();  // adjust_sites' topology
    std::vector<SurfacePoint> sites = r.lloyd.sites;
    const int32_t removed = adjust_sites(L, dual, r.lloyd.label, drop, sites, added);
    st.ctx.check_cancel();
    LloydOptions ro = L.lo;
    ro.keep_voronoi = st.incremental;
    if (relax && drop > 0 && static_cast<int32_t>(sites.size()) > pre + drop / 2) {
      // Most cells may not go (the repair's sites, their neighbors and the
      // boundary cells hold them: many holes or small components): Lloyd
      // afresh with `pre` sites, whose repair adds what the topology needs.
      ro.sites = pre;
      r.removed_sites += static_cast<int32_t>(r.lloyd.sites.size()) - pre;
      added.assign(static_cast<size_t>(pre), 0);
      r.lloyd_iterations += adopt_cells(cvt_lloyd(*L.m, *L.d, ro, st.ctx.sub(p, p)), r.lloyd);
    } else {
      r.removed_sites += removed;
      ro.iterations = relax ? st.o.density_iterations : 0;
      ro.init_radius = std::min(L.lo.init_radius, 2.5);
      r.lloyd_iterations += adopt_cells(cvt_lloyd(*L.m, *L.d, std::move(sites), ro, st.ctx.sub(p, p)), r.lloyd);
    }
    ++r.density_passes;
    r.repair_s += st.sw.lap();
    dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
    r.dual_s += st.sw.lap();
    dual = repair(st, L, std::move(dual), p, p);
    added.resize(r.lloyd.sites.size(), 1);
  }
  if (best && (dual.defects.total() > 0 || std::abs(cells_of(dual) - want) > std::abs(best->error))) {
    while (r.refinements > best->refinements) {
      st.keep.meshes.pop_back();
      st.keep.derived.pop_back();
      if (st.keep.ops.size() > st.keep.meshes.size()) st.keep.ops.pop_back();
      --r.refinements;
    }
    r.lloyd = std::move(best->lloyd);
    r.added_sites = best->added_sites;
    r.removed_sites = best->removed_sites;
    L = best->L;
    return std::move(best->dual);
  }
  return dual;
}

// Sites on the input's features (remesh_features.hpp) replace the Lloyd
// sites within half a mean edge of them; the sites are labelled again (they
// stay where they are) and the partition repaired. The feature sites come
// first, so the repair's sites (appended) keep their ids.
RestrictedDual insert_features(const RepairStage& st, Level& L, RestrictedDual dual, double p) {
  RemeshResult& r = st.r;
  if (st.o.corners_needed) st.o.corners_needed();
  FeatureGraph g = feature_graph(*L.m, *L.d, st.o.feature_angle_deg);
  const double area = std::accumulate(L.d->mass.begin(), L.d->mass.end(), 0.0);
  const double spacing = feature_spacing(area, st.o.lloyd.sites);
  drop_short_components(*L.m, g, spacing);
  if (g.edges == 0) return dual;
  // On a subdivided level every input edge is 2^k edges (k levels).
  int levels = 0;
  for (size_t k = 0; k < st.keep.meshes.size(); ++k)
    if (L.m == &st.keep.meshes[k]) levels = static_cast<int>(k) + 1;
  r.feature_edges = g.edges >> levels;
  r.feature_curves = static_cast<int32_t>(g.curves.size());
  r.feature_corners = static_cast<int32_t>(g.corners.size());
  int32_t count = 0;
  const int32_t want = dual.defects.total() == 0 ? cells_of(dual) : static_cast<int32_t>(r.lloyd.sites.size());
  std::vector<SurfacePoint> sites =
      with_feature_sites(*L.m, *L.d, g, r.lloyd.sites, spacing, 0.5, count, &r.feature_lines);
  const std::vector<SurfacePoint> fixed(sites.begin(), sites.begin() + count);
  st.ctx.check_cancel();
  LloydOptions ro = L.lo;
  ro.iterations = 0;  // labels, then the band's lost sites in the largest cells
  ro.init_radius = std::min(L.lo.init_radius, 2.5);
  const RunContext part = st.ctx.sub(p, p);
  LloydResult lr = cvt_lloyd(*L.m, *L.d, std::move(sites), ro, part);
  const int32_t short_by = want - static_cast<int32_t>(lr.sites.size());
  sites = split_largest_cells(*L.m, *L.d, lr.label, std::move(lr.sites), short_by, count);
  ro.iterations = 1;  // the free sites relax around the feature sites, put back after each iteration
  for (int it = 0; it < st.o.density_iterations; ++it) {
    lr = cvt_lloyd(*L.m, *L.d, std::move(sites), ro, part);
    r.lloyd_iterations += static_cast<int32_t>(lr.iter_s.size());
    sites = std::move(lr.sites);
    std::copy(fixed.begin(), fixed.end(), sites.begin());
  }
  ro.iterations = 0;
  ro.keep_voronoi = st.incremental;
  adopt_cells(cvt_lloyd(*L.m, *L.d, std::move(sites), ro, part), r.lloyd);
  r.repair_s += st.sw.lap();
  dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
  r.dual_s += st.sw.lap();
  r.feature_sites = count;
  return repair(st, L, std::move(dual), p, p);
}

}  // namespace

RemeshResult cvt_remesh(const Mesh& m, const MeshDerived& d, const RemeshOptions& o, const RunContext& ctx) {
  if (o.max_repair_rounds < 0 || o.relax_iterations < 0 || o.max_refinements < 0)
    fail(ErrorCode::BadUsage, "cvt remesh: repair rounds, relaxation iterations and refinements must be >= 0");
  if (!(o.feature_angle_deg >= 0 && o.feature_angle_deg < 180))
    fail(ErrorCode::BadUsage, "cvt remesh: the feature angle must be in [0, 180) degrees (0: no features), got " +
                                  std::to_string(o.feature_angle_deg));
  RemeshResult r;
  BatchStopwatch sw;
  Level L{&m, &d, o.lloyd, {}};
  // One factor for every round (isotropic cells; the lifted metric is factored per run).
  HeatDiffusion own;
  double lloyd_begin = 0.0;  // after the factorization's share of the progress, when it runs here
  if (!L.lo.prepared && L.lo.anisotropy == 0) {
    lloyd_begin = 0.3;
    own = prepare_heat_diffusion(m, d, L.lo.t_factor, L.lo.t_abs, ctx.sub(0.0, lloyd_begin));
    L.lo.prepared = &own;
    r.factor_s = sw.lap();
  }
  // One monotone progress fraction: the Lloyd iterations, each repair round's share, then
  // the dual and its optimization (refined levels report no progress of their own).
  constexpr double kLloydEnd = 0.7, kRepairEnd = 0.9;
  // Repair rounds without relaxation only add sites: they grow the final
  // diagram (heat_voronoi_add) instead of relabelling from scratch.
  const bool incremental =
      o.relax_iterations == 0 && L.lo.prepared && L.lo.solver == LloydOptions::Solver::Local;
  L.lo.keep_voronoi = incremental;
  // Cells of fewer than min_vertices_per_site input vertices: Lloyd runs on a
  // subdivided input from the start (the requested density, fewer defects),
  // within max_refinements unless there are more sites than input vertices
  // (points on the continuous surface, as many as asked: the caller bounds the
  // subdivision's memory).
  Levels keep;
  const double want = o.min_vertices_per_site * L.lo.sites;
  const bool dense = L.lo.sites > m.num_vertices();
  for (double nv = m.num_vertices();; nv *= 4) {  // 4x per level: the estimate the sample tables were made with
    if (dense ? L.m->num_vertices() >= want : nv >= want || r.refinements >= o.max_refinements) break;
    if (o.corners_needed) o.corners_needed();  // the subdivision reads the input's face_vertices
    L = finer(L, false, keep, ctx.sub(lloyd_begin, lloyd_begin), r);
  }
  r.lloyd = cvt_lloyd(*L.m, *L.d, L.lo, ctx.sub(lloyd_begin, kLloydEnd));
  r.lloyd_iterations = static_cast<int32_t>(r.lloyd.iter_s.size());
  if (o.lloyd_done) o.lloyd_done();  // d.incidence is read from here on
  r.lloyd_s = sw.lap();
  // The input's dual topology on the derived data's edge incidence (not a
  // second one, ~45 MB at 416k vertices; copies of the level share it).
  if (L.m == &m) L.topo = dual_topology(m, d.incidence);
  RestrictedDual dual = restricted_dual(*L.m, L.topo, r.lloyd.label, r.lloyd.sites);
  r.first_defects = dual.defects;
  r.dual_s += sw.lap();
  const RepairStage st{m, o, incremental, keep, ctx, sw, r};
  dual = repair(st, L, std::move(dual), kLloydEnd, kRepairEnd);
  dual = meet_density(st, L, std::move(dual), kRepairEnd);
  if (o.feature_angle_deg > 0) dual = insert_features(st, L, std::move(dual), kRepairEnd);
  ctx.check_cancel();
  ctx.report(kRepairEnd, "remesh");
  r.defects = dual.defects;
  r.complete = dual.defects.total() == 0;
  r.requested = o.lloyd.sites;
  r.repair_sites = r.added_sites;
  r.added_sites = static_cast<int32_t>(r.lloyd.sites.size()) - r.requested;  // net: sites = requested + added
  // The repair's top-K lists and dual topology: not read by the assembly (~20 MB at 416k vertices).
  r.lloyd.voronoi = HeatVoronoi{};
  L.topo = DualTopology{};
  // No heat solve after the repair: the operator goes before the assembly allocates.
  L.lo.prepared = nullptr;
  own = HeatDiffusion{};
  keep.ops.clear();  // the finer levels' operators (their meshes stay: back_to_input)
  if (o.operator_done) o.operator_done();
  if (o.corners_needed) o.corners_needed();  // the factor out first: the assembly reads them
  if (r.complete) assemble_remesh(m, *L.m, dual, o, sw, r);
  r.delivered = r.remesh.num_vertices();
  back_to_input(m, keep.meshes, r.lloyd);
  ctx.report(1.0, "remesh");
  return r;
}

}  // namespace locus

