// Heat-diffusion Voronoi diagrams on triangle meshes (thesis §3.4, eqs. 3.15-3.21;
// heat sources §3.2, eqs. 3.7, 3.8).
//
// The operator and its solves are the kernels' heat module: one prepared
// HeatDiffusion (kernels/heat/heat_diffusion.hpp) serves every generator, solved
// 8 at a time (kernels/heat/heat_batch.hpp); generators are SurfacePoints
// (kernels/heat/surface_point.hpp).
// query: the heat of generator p is u = (M - t L_C)^{-1} b(p) (eqs. 3.7, 3.8: M h with
// h = M^{-1} b(p)), b(p) the hat functions at p (the barycentric weights of p in its
// face, or e_v for a vertex). The label of vertex i is argmax_j u_ij (eq. 3.18);
// every vertex also keeps its kVoronoiTopK largest heat values, which is what the
// per-triangle diagram extraction (eqs. 3.19-3.21) needs: the heat of a neighbor's
// label at this vertex. Values missing from that list are solved for afterwards
// (rare: the neighbor's generator is then not among this vertex's four hottest).
//
// Localized mode (thesis §3.6, §3.7.1): with a neighborhood per generator, each
// batch of 8 is solved by the approximate selective solve (Algorithm 2) on the union
// of the 8 neighborhoods; a vertex outside a batch's kept set takes no value from
// that batch. Each batch sends its hottest K sites per vertex, so the serial merge
// usually stops after one comparison. Vertices no batch reached get the label of
// the nearest labelled vertex (breadth-first, deterministic) and are counted.
//
// Determinism: argmax and top-K use the total order (heat descending, generator id
// ascending), so merging batches in any order gives the same result whatever the
// thread count (batches run through kernels/parallel/batch_graph.hpp).
// Thread safety: queries on one prepared HeatDiffusion may run concurrently.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"

namespace locus {

inline constexpr int kVoronoiTopK = 4;

struct HeatVoronoi {
  HostVector<int32_t> label;      // nv: generator with the largest heat (eq. 3.18)
  HostVector<int32_t> top_site;   // nv * top_k, -1 where fewer values were seen (keep_hottest_only: empty if = label)
  HostVector<double> top_value;   // nv * top_k, descending per vertex
  int32_t top_k = kVoronoiTopK;   // entries per vertex: kVoronoiTopK, or 1 after keep_hottest_only
  // Empty (vertex v's entries are [v top_k, (v + 1) top_k)), or nv + 1 after
  // keep_split_rows: vertex v's entries are [top_offsets[v], top_offsets[v + 1]).
  HostVector<int32_t> top_offsets;
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
                                 std::span<const HostVector<int32_t>> batch_kept, const RunContext& ctx);
// The same with each batch's kept set produced where its solve needs it:
// batch_kept(b, kept) appends batch b's set to `kept` (called from the solve
// tasks, several at once). Lloyd's method rebuilds them from its cell graph
// instead of holding every batch's list (~12 MB at 416k vertices).
using BatchKept = std::function<void(int32_t batch, HostVector<int32_t>& kept)>;
HeatVoronoi heat_voronoi_batched(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites,
                                 std::span<const int32_t> batch_order, const BatchKept& batch_kept,
                                 const RunContext& ctx);

// Keeps of V's top-K lists the hottest entry per vertex (top_k = 1): the label's
// heat, all that heat_voronoi_add compares new generators with (its labels are
// the same as with the full lists: the hottest of a merge in the total order
// does not depend on the colder entries). A CVT repair holds V between its
// rounds (cvt_remesh.hpp): 3.3 MB instead of 20 MB at 416k vertices, the
// hottest sites being the labels (top_site left empty; kept when a vertex was
// labelled by the breadth-first fallback). The diagram extraction and the cell
// partition need the full lists and refuse such a V.
void keep_hottest_only(HeatVoronoi& V);

// Keeps of V's top-K lists the entries the split triangles read: at a corner v
// of a triangle of m whose corners have different labels, the heat of that
// triangle's labels (the entries of v's list whose site is one of them), in
// vertex order and, per vertex, in list order; V.top_offsets gives each
// vertex's entries (none where no split triangle reads one). The cells'
// split-triangle loads (voronoi_cell_partition.hpp accumulate_cell_load,
// cell_areas) read no other entry and miss the same ones, so they are the same.
// Lloyd's centroid steps hold the labels' lists so: ~6 MB instead of 20 MB at
// 416k vertices and 10,000 sites. The diagram extraction, the cell partition,
// heat_voronoi_add and keep_hottest_only refuse such a V; a second call too.
void keep_split_rows(HeatVoronoi& V, const Mesh& m);

// Adds generators to a diagram: V is the diagram of sites[0 .. first_new) (from
// the functions above; its top-K lists are kept, or their hottest entries only:
// keep_hottest_only) and sites[first_new ..] are
// new. Only the new generators are solved, 8 at a time in `new_order` (a
// permutation of first_new .. sites.size()-1; empty = ascending), each on its
// own neighborhood (new_neighborhoods[s - first_new]; localized as above), and
// merged into V's top-K lists; then the labels are recomputed. A new generator
// takes the vertices of its neighborhood where it is hotter than the old label;
// elsewhere nothing changes. The same total order as above: deterministic.
// Costs the new generators' solves only (CVT remeshing's repair rounds add a
// few sites to thousands: cvt_remesh.hpp).
void heat_voronoi_add(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> sites, int32_t first_new,
                      std::span<const std::vector<int32_t>> new_neighborhoods, std::span<const int32_t> new_order,
                      HeatVoronoi& V, const RunContext& ctx);

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

}  // namespace locus
