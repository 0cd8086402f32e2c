// Heat-diffusion Voronoi diagrams on triangle meshes (thesis §3.4, eqs. 3.15-3.21;
// heat sources §3.2, eqs. 3.7, 3.8).
//
// prepare: t = t_factor * h^2 (h = mean edge length; thesis §3.7 uses t = h^2) or an
// absolute t; one METIS ordering, one symbolic and one numeric factor of the heat
// operator M - t L_C. That single factor serves every generator.
// query: the heat of generator p is u = (M - t L_C)^{-1} b(p) (eqs. 3.7, 3.8: M h with
// h = M^{-1} b(p)), b(p) the hat functions at p (the barycentric weights of p in its
// face, or e_v for a vertex). Generators are solved 8 at a time (8-lane solves). The
// label of vertex i is argmax_j u_ij (eq. 3.18); every vertex also keeps its
// kVoronoiTopK largest heat values, which is what the per-triangle diagram extraction
// (eqs. 3.19-3.21) needs: the heat of a neighbor's label at this vertex. Values
// missing from that list are solved for afterwards (rare: the neighbor's generator
// is then not among this vertex's four hottest).
//
// Localized mode (thesis §3.6, §3.7.1): with a neighborhood per generator, each
// batch of 8 is solved by the approximate selective solve (Algorithm 2) on the union
// of the 8 neighborhoods (kernels/solve_selective: the forward substitution skips
// the part of the etree that only feeds zeroed entries); a vertex outside a batch's
// kept set takes no value from that batch. Each batch sends its hottest K sites per
// vertex, so the serial merge usually stops after one comparison. Vertices no batch reached get the label of the nearest labelled
// vertex (breadth-first, deterministic) and are counted.
//
// Determinism: argmax and top-K use the total order (heat descending, generator id
// ascending), so merging batches in any order gives the same result whatever the
// thread count.
// Thread safety: a prepared HeatDiffusion is immutable; queries may run concurrently.
#pragma once
#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus {

// A point on a triangle mesh: barycentric weights (summing to 1) of the corners
// f0[face], f1[face], f2[face], or a vertex when face < 0.
struct SurfacePoint {
  int32_t face = -1;
  int32_t vertex = -1;
  std::array<double, 3> bary{1.0, 0.0, 0.0};
};
inline SurfacePoint vertex_point(int32_t v) { return SurfacePoint{-1, v, {1.0, 0.0, 0.0}}; }
// Throws BadUsage naming `what` and `index` unless p is a vertex or a face of m with
// finite barycentric weights >= -1e-9 summing to 1 (within 1e-9).
void check_surface_point(const Mesh& m, const SurfacePoint& p, const char* what, size_t index);
// Position in R^3.
std::array<double, 3> surface_point_position(const Mesh& m, const SurfacePoint& p);
// Hat-function weights of p: up to 3 (vertex, weight) pairs with weight > 0; returns the count.
int surface_point_support(const Mesh& m, const SurfacePoint& p, int32_t v[3], double w[3]);

// `count` points uniformly distributed by area (face chosen with probability
// proportional to its area, barycentric weights uniform on the triangle), from a
// splitmix64 stream seeded with `seed`: the same on every platform.
std::vector<SurfacePoint> random_surface_points(const Mesh& m, int32_t count, uint64_t seed);

// The prepared heat operator (immutable after preparation).
struct HeatDiffusion {
  int32_t n = 0;
  double h = 0;  // mean edge length in the operator's metric
  double t = 0;  // diffusion time used
  std::vector<double> mass;  // lumped mass in the operator's metric
  NumericFactor factor;
  double operator_s = 0, order_s = 0, analyze_s = 0, factor_s = 0;
};
// Isotropic operator M - t L_C of m; t = t_abs when t_abs > 0, else t_factor * h^2.
// Requires a manifold triangle mesh without degenerate faces or unreferenced vertices.
HeatDiffusion prepare_heat_diffusion(const Mesh& m, double t_factor, double t_abs, const RunContext& ctx);
// The same with m's derived data (kernels/include/locus/kernels/mesh/mesh_derived.hpp): h and the
// lumped mass are taken from d, and the requirements are checked unless d.checked covers them.
HeatDiffusion prepare_heat_diffusion(const Mesh& m, const MeshDerived& d, double t_factor, double t_abs,
                                     const RunContext& ctx);
// Any operator A = M - t L already built (e.g. on a lifted metric, pipelines/cvt_lloyd),
// with its lumped mass, mean edge length and t.
HeatDiffusion prepare_heat_diffusion(const CscMatrix& A, std::vector<double> mass, double h, double t,
                                     const RunContext& ctx);

// One batch of up to 8 heat sources, solved in full (kept empty) or by the
// approximate selective solve on `kept` (unique vertex ids, any order). Inputs:
// lane l's source is src_vertex/src_weight[src_offsets[l] .. src_offsets[l+1]);
// lanes beyond src_offsets.size()-1 are zero. Output: values[k * 8 + lane] at
// vertex id(k), k < count(). The rest is reusable scratch (one HeatBatch per thread).
struct HeatBatch {
  std::vector<int32_t> src_offsets{0};
  std::vector<int32_t> src_vertex;
  std::vector<double> src_weight;
  std::vector<int32_t> kept;
  std::vector<double> values;

  int32_t count() const { return full_ ? n_ : static_cast<int32_t>(kept.size()); }
  int32_t id(int32_t k) const { return full_ ? k : kept[k]; }
  void clear_sources() { src_offsets.assign(1, 0); src_vertex.clear(); src_weight.clear(); }
  void add_source(std::span<const int32_t> v, std::span<const double> w) {
    src_vertex.insert(src_vertex.end(), v.begin(), v.end());
    src_weight.insert(src_weight.end(), w.begin(), w.end());
    src_offsets.push_back(static_cast<int32_t>(src_vertex.size()));
  }

  bool full_ = true;
  int32_t n_ = 0;
  SolveWorkspace ws_;
  SolvePlan plan_;      // reused: planning does not allocate once warm
  PlanWorkspace pws_;
  std::vector<double> work_, rhs_;
  std::vector<int32_t> support_;
  std::vector<uint8_t> mark_;  // n, zero between uses
  std::vector<int32_t> spos_;  // n, -1 between uses: position of a source vertex in support_
};
void solve_heat_batch(const HeatDiffusion& H, HeatBatch& b);
// Removes repeated ids from b.kept, keeping first occurrences in order (O(|kept|),
// no sort); throws BadUsage for ids outside 0..n-1.
void dedupe_kept(HeatBatch& b, int32_t n);

inline constexpr int kVoronoiTopK = 4;

struct HeatVoronoi {
  std::vector<int32_t> label;      // nv: generator with the largest heat (eq. 3.18)
  std::vector<int32_t> top_site;   // nv * kVoronoiTopK, -1 where fewer values were seen
  std::vector<double> top_value;   // nv * kVoronoiTopK, descending per vertex
  int64_t unreached = 0;           // vertices labelled by the breadth-first fallback
  int32_t batches = 0;
  int64_t solved_entries = 0;      // sum over batches of the entries computed (n per full batch)
  double solve_cpu_s = 0;          // thread CPU time in the solves, summed over batches (timing only)
};

// neighborhoods: empty (full solves) or one sorted vertex list per generator
// (approximate selective solves on the union over each batch of 8).
// Generators are processed in the order of `batch_order` (a permutation of the
// generator ids; empty = identity): consecutive runs of 8 form a batch, so spatially
// sorted orders give compact unions.
HeatVoronoi heat_voronoi(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                         std::span<const std::vector<int32_t>> neighborhoods, std::span<const int32_t> batch_order,
                         const RunContext& ctx);
// The same with one kept set per batch instead of per generator: batch b (the
// generators batch_order[8b .. 8b+7]) is solved on batch_kept[b] (vertex ids, any
// order; repeats allowed) plus its generators' supports. Lloyd's method passes the
// union of the batch's cells and their two rings of neighbor cells, built once per
// batch and shared with its centroid solves.
HeatVoronoi heat_voronoi_batched(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                 std::span<const int32_t> batch_order,
                                 std::span<const std::vector<int32_t>> batch_kept, const RunContext& ctx);

// The diagram as line segments (eqs. 3.19-3.21). Points on mesh edges are shared
// by the two triangles of the edge; Voronoi corners (triangles with three labels,
// eq. 3.21) are extra points joined to the three edge points.
struct VoronoiDiagram {
  std::vector<double> points;              // 3 per point
  std::vector<int32_t> point_edge_sites;   // 2 per point: the two labels an edge point separates (-1,-1 at corners)
  std::vector<int32_t> segments;           // 2 per segment: point ids
  std::vector<std::vector<int32_t>> polylines;  // the segments chained at points of degree 2
  int64_t corners = 0;
  int64_t resolved_missing = 0;            // heat values solved for because they were not in the top-K lists
};
VoronoiDiagram extract_voronoi_diagram(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                       const HeatVoronoi& V, const RunContext& ctx);

// Runs work items 0..count-1 through a oneTBB flow graph inside an arena of
// ctx.threads threads: `solve(i)` (a function_node with unlimited concurrency)
// returns a std::shared_ptr<Msg>, `reduce(msg)` (a serial function_node) merges
// it. Callers make the reduction independent of arrival order (a total order or
// per-item slots merged afterwards in item order), so results do not depend on
// the thread count. Cancellation is polled before each item; no exception leaves
// a node: the first one (lowest item id) is stored and rethrown after
// wait_for_all(). `phase` (nullptr = silent) names the progress reports.
template <class Msg, class Solve, class Reduce>
void run_batch_graph(const RunContext& ctx, int32_t count, Solve&& solve, Reduce&& reduce, const char* phase) {
  if (count <= 0) return;
  struct Item {
    int32_t id = -1;
    std::shared_ptr<Msg> msg;
  };
  std::mutex mu;
  std::exception_ptr err;
  int32_t err_id = INT32_MAX;
  std::atomic<bool> stop{false};
  int32_t done = 0;
  auto record = [&](int32_t id) {
    std::lock_guard<std::mutex> lock(mu);
    if (id < err_id) {
      err_id = id;
      err = std::current_exception();
    }
    stop.store(true);
  };
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  run_with_threads(std::max(1, threads), [&] {  // reused arena: one per call leaks inside oneTBB
    tbb::flow::graph g;
    tbb::flow::function_node<int32_t, Item> work(g, tbb::flow::unlimited, [&](int32_t id) -> Item {
      if (stop.load() || ctx.cancelled()) {
        stop.store(true);
        return {id, nullptr};
      }
      try {
        return {id, solve(id)};
      } catch (...) {
        record(id);
        return {id, nullptr};
      }
    });
    tbb::flow::function_node<Item> merge(g, tbb::flow::serial, [&](const Item& it) -> tbb::flow::continue_msg {
      if (!it.msg || stop.load()) return {};
      try {
        reduce(it.msg);
        ++done;
        if (phase) ctx.report(static_cast<double>(done) / count, phase);
      } catch (...) {
        record(it.id);
      }
      return {};
    });
    tbb::flow::make_edge(work, merge);
    for (int32_t i = 0; i < count; ++i) work.try_put(i);
    g.wait_for_all();
  });
  if (err) std::rethrow_exception(err);
  ctx.check_cancel();
}

// Lap timer for phase timings, in seconds.
class BatchStopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace locus
