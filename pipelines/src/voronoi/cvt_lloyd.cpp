// The Lloyd loop of the heat-diffusion CVT, localized
// (pipelines/include/locus/pipelines/voronoi/cvt_lloyd.hpp; thesis §3.7.1, §3.4-3.6): labels,
// batches of neighboring cells, their sources, centroid solves and refinement,
// statistics, the move. Its set-up is in cvt_lloyd_setup.cpp, the cells' graph in
// cell_graph.cpp, the first neighborhoods in site_neighborhoods.cpp, the lifted
// metric in kernels/mesh/lifted_metric.cpp.
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/core/release_free_memory.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>

#include "cvt_lloyd_setup.hpp"
#include "locus/error.hpp"
#include "locus/kernels/heat/heat_batch.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/morton_order.hpp"
#include "locus/kernels/parallel/batch_graph.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"
#include "locus/kernels/parallel/progress_ticker.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_selective.hpp"
#include "locus/pipelines/voronoi/cell_graph.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"
#include "locus/pipelines/voronoi/heat_centroid.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"
#include "locus/pipelines/voronoi/voronoi_cell_partition.hpp"

namespace locus {

namespace {

// Morton order of the sites' positions: batches of 8 consecutive sites are compact,
// so the unions of their neighborhoods stay small.
std::vector<int32_t> spatial_order(const Mesh& m, std::span<const SurfacePoint> sites) {
  const size_t ns = sites.size();
  std::vector<double> p(3 * ns);
  for (size_t s = 0; s < ns; ++s) {
    const auto x = surface_point_position(m, sites[s]);
    std::copy(x.begin(), x.end(), p.begin() + 3 * s);
  }
  std::vector<uint64_t> code(ns);
  morton_codes_in_box(p, code);
  std::vector<int32_t> order(ns);
  MortonWorkspace ws;
  morton_order(code, order, ws);
  return order;
}

struct CentroidMsg {
  int32_t cells[kLanes];
  HeatCentroid result[kLanes];
  int lanes = 0;
  int32_t batch = 0;
  int64_t kept = 0;
  int64_t reads = 0, label_reads = 0;  // factor entries read (count_reads)
  double solve_cpu_s = 0;
  double energy[kLanes] = {};
  double area_centroid[kLanes][3] = {};  // sum_i b_i x_i / sum_i b_i of the cell's source
  int64_t fallback = 0;
};

struct CentroidScratch {
  HeatBatch batch;
  HostVector<double> dense;  // full solves only: n, zero between uses
  std::vector<int32_t> cells, touched;
  // (batch.vertex_map(): n, -1 between uses) a cell's load slots (split faces),
  // then the position of a kept vertex in the batch's solution (the fits), beside
  // the solve's own uses of that map. No dense n-vector of loads.
  std::vector<double> weights;
  std::vector<uint8_t> read_mark;   // count_reads scratch
  std::vector<int32_t> label_support;
  SolvePlan label_plan;
  PlanWorkspace label_pws;
};

// What the Lloyd iterations read and never change.
struct LloydInputs {
  const Mesh& m;
  const LloydOptions& opt;
  const RunContext& ctx;
  const HeatDiffusion& H;   // cells (labels)
  const HeatDiffusion& Hc;  // centroids
  const CentroidGeometry& geo;
  const Adjacency& adj;              // the cell graph's edges
  VertexStars& stars;                // in the operator's metric (isotropic: areas out during the labels)
  const HostVector<double>& area_r3;
  const HostVector<double>& mass_r3;
  double h_r3;
  int threads;                       // of the arena of the cell partitions (>= 1)
  std::span<const double> mass_c;    // Hc's lumped masses (LloydOperators::mass_c)
};

// This iteration's centroid step: one slot per cell, filled as the batches arrive
// (arrival order is irrelevant), and per-batch factor reads (count_reads).
struct CentroidSlots {
  std::vector<HeatCentroid> cent;
  std::vector<double> cell_energy;
  std::vector<uint8_t> has;
  std::vector<double> bias;
  std::vector<int64_t> centroid_reads, label_reads;
  size_t kept_base = 0;  // this iteration's first entry of kept_fraction_
  int64_t fallback = 0;
};

// Lloyd's iterations on the current sites: labels, batches of neighboring cells,
// their sources, heat centroids and refinement, statistics, the move; then the
// final labels. Writes the result's per-iteration series and totals.
class LloydLoop {
 public:
  LloydLoop(const LloydInputs& in, std::vector<SurfacePoint>& sites, std::vector<std::vector<int32_t>> nb,
            LloydResult& r)
      : in_(in), m_(in.m), opt_(in.opt), ctx_(in.ctx), local_(in.opt.solver == LloydOptions::Solver::Local),
        n_(in.m.num_vertices()), ns_(static_cast<int32_t>(sites.size())), sites_(sites), nb_(std::move(nb)), r_(r),
        full_entries_(in.opt.count_reads ? factor_entries(*in.H.factor.symbolic) : 0) {}

  void iterate(int32_t it);
  void finish();
  // Localized first labels from given cells (e.g. geodesic_site_cells) instead of
  // per-site neighborhoods: batches and kept sets as every later iteration's.
  void first_cells(std::span<const int32_t> label);

 private:
  template <class F>
  void in_arena(F&& f) {  // reused per (thread, concurrency): an arena per call leaks inside oneTBB
    run_with_threads(in_.threads, f);
  }
  // for_centroids: V_ keeps the split triangles' rows only (keep_split_rows).
  void labels_of_sites(bool for_centroids);
  // This iteration's share of the progress (iteration it of n: [it, it + 1) / (n + 1); the final labels last).
  RunContext step_context(int32_t it, double begin, double end) const {
    const double n = std::max(1, opt_.iterations) + 1.0;
    return ctx_.sub((it + begin) / n, (it + end) / n);
  }
  CentroidSlots centroid_slots(int32_t nbatch);
  std::shared_ptr<CentroidMsg> solve_centroid_batch(int32_t b, std::span<const std::array<double, 3>> before);
  void add_cell_source(CentroidScratch& cs, CentroidMsg& msg, int l, int32_t c, const std::array<double, 3>& p);
  void count_batch_reads(CentroidScratch& cs, CentroidMsg& msg, int32_t b);
  void refine_centroids(CentroidScratch& cs, CentroidMsg& msg);
  void store(const CentroidMsg& msg, CentroidSlots& slots);
  void record_statistics(CentroidSlots& slots, int32_t nbatch);
  void move_sites(const CentroidSlots& slots, std::span<const std::array<double, 3>> before);

  const LloydInputs in_;
  const Mesh& m_;
  const LloydOptions& opt_;
  const RunContext& ctx_;
  RunContext labels_ctx_;  // the labels' part of the current iteration (one monotone fraction per call)
  const bool local_;
  const int32_t n_, ns_;
  std::vector<SurfacePoint>& sites_;
  std::vector<std::vector<int32_t>> nb_;  // first neighborhoods (localized), until the first labels
  LloydResult& r_;
  HeatVoronoi V_;
  CellGraph cells_;
  tbb::enumerable_thread_specific<CentroidScratch> cscratch_;
  std::vector<double> kept_fraction_;  // per centroid batch, summed in batch order at the end
  // Batches (runs of 8 in `order_`) and, localized, each batch's kept set: the union of
  // its cells and their two rings of neighbor cells (batch_kept). The centroid step
  // builds them from the labels of this iteration and the next labels solve on the
  // same sets (same batches: the sites are the centroids of these cells), rebuilt
  // from the same cell graph where each solve needs its set instead of held for
  // every batch between the two (~12 MB at 416k vertices).
  std::vector<int32_t> order_;
  bool batches_ = false;  // order_ and cells_ give the next labels' kept sets
  void batch_kept(int32_t b, HostVector<int32_t>& kept) const;
  const int64_t full_entries_;
  double centroid_read_sum_ = 0, label_read_sum_ = 0;
  int64_t read_batches_ = 0;
};

void LloydLoop::first_cells(std::span<const int32_t> label) {
  in_arena([&] {
    cells_ = build_cell_graph(in_.adj, label, ns_);
    order_ = cluster_order(cells_, spatial_order(m_, sites_), kLanes);
  });
  batches_ = true;
  nb_ = {};
}

// Batch b's kept set, appended: the vertices of its cells and their two rings of
// neighbor cells in cells_ (the centroid step's hb.kept of the same batch).
void LloydLoop::batch_kept(int32_t b, HostVector<int32_t>& kept) const {
  std::vector<int32_t> cells;
  for (int32_t i = b * kLanes; i < std::min(ns_, (b + 1) * kLanes); ++i) append_two_ring_cells(cells_, order_[i], cells);
  append_cells_vertices(cells_, cells, kept);
}

void LloydLoop::labels_of_sites(bool for_centroids) {
  // The centroid step's per-thread solve workspaces (8 n doubles each) are not
  // needed while the labels' own are: freed, not held across the whole loop.
  cscratch_.clear();
  V_ = HeatVoronoi{};  // the last labels' top-K lists: not held while the new ones fill
  // Isotropic: the stars' areas are face_areas(m) (moved there), read by no
  // label: rebuilt after them (6.7 MB of their peak at 416k vertices).
  const bool areas_out = opt_.anisotropy == 0;
  if (areas_out) in_.stars.area = HostVector<double>();
  // What was just freed (the workspaces ~50 MB at 416k vertices, in the worker
  // threads' heaps) is not kept resident through the labels' peak.
  release_free_memory();
  BatchStopwatch psw;
  if (order_.empty()) order_ = spatial_order(m_, sites_);
  if (local_ && batches_) {
    V_ = heat_voronoi_batched(
        in_.H, m_, sites_, order_, [this](int32_t b, HostVector<int32_t>& kept) { batch_kept(b, kept); },
        labels_ctx_);
  } else {  // first labels: per-site Dijkstra balls (localized) or full solves
    V_ = heat_voronoi(in_.H, m_, sites_, local_ ? std::span<const std::vector<int32_t>>(nb_)
                                                 : std::span<const std::vector<int32_t>>(),
                      order_, labels_ctx_);
    nb_ = {};
  }
  r_.unreached += V_.unreached;
  r_.label_solve_cpu_s += V_.solve_cpu_s;
  r_.labels_s += psw.lap();
  for (int32_t v = 0; v < n_; ++v)
    if (V_.label[v] < 0)
      fail(ErrorCode::Numerical, "cvt: vertex " + std::to_string(v) + " received heat from no site");
  in_arena([&] { cells_ = build_cell_graph(in_.adj, V_.label, ns_); });
  // The centroid step reads the heat at the split triangles' corners only.
  if (for_centroids) keep_split_rows(V_, m_);
  // That and the labels' solve workspaces and batch lists, freed: not resident
  // through the centroid step (~25 MB of a 416k-vertex remesh's peak).
  release_free_memory();
  if (areas_out) in_.stars.area = face_areas(m_);
  r_.partition_s += psw.lap();
}

CentroidSlots LloydLoop::centroid_slots(int32_t nbatch) {
  CentroidSlots s;
  s.cent.resize(ns_);
  s.cell_energy.assign(ns_, 0.0);
  s.has.assign(ns_, 0);
  s.bias.assign(ns_, 0.0);
  batches_ = local_;
  s.kept_base = kept_fraction_.size();
  s.centroid_reads.assign(nbatch, 0);
  s.label_reads.assign(nbatch, 0);
  kept_fraction_.resize(s.kept_base + nbatch, 0.0);
  return s;
}

// Lane l of a centroid batch: cell c's Euclidean CVT energy w.r.t. its current site
// p (diagnostic), its source (the split triangles or the vertex masses of the cell)
// added to the batch, and that source's area centroid.
void LloydLoop::add_cell_source(CentroidScratch& cs, CentroidMsg& msg, int l, int32_t c,
                                const std::array<double, 3>& p) {
  const Mesh& m = m_;
  const std::span<const int32_t> cv(cells_.verts.data() + cells_.offsets[c],
                                    static_cast<size_t>(cells_.offsets[c + 1] - cells_.offsets[c]));
  {  // Euclidean CVT energy of the cell w.r.t. its current site (diagnostic)
    double e = 0;
    for (int32_t v : cv)
      e += in_.mass_r3[v] * ((m.x[v] - p[0]) * (m.x[v] - p[0]) + (m.y[v] - p[1]) * (m.y[v] - p[1]) +
                             (m.z[v] - p[2]) * (m.z[v] - p[2]));
    msg.energy[l] = e;
  }
  cs.touched.clear();
  cs.weights.clear();
  if (opt_.split_faces) {  // int_C phi_i over the split triangles (eqs. 3.9-3.11), this cell only
    accumulate_cell_load(in_.stars, V_, c, cv, cs.batch.vertex_map(n_), cs.weights, cs.touched, msg.fallback);
    cs.batch.add_source(cs.touched, cs.weights);
    area_centroid(m, cs.touched, cs.weights, msg.area_centroid[l]);
  } else {
    for (int32_t v : cv) cs.weights.push_back(in_.mass_c[v]);  // M chi_C (eqs. 3.7, 3.10)
    cs.batch.add_source(cv, cs.weights);
    area_centroid(m, cv, cs.weights, msg.area_centroid[l]);
  }
}

// count_reads: the factor entries this batch's centroid solve read and those the
// next labels' solve of the same batch will read (the sites' supports on the same
// kept set).
void LloydLoop::count_batch_reads(CentroidScratch& cs, CentroidMsg& msg, int32_t b) {
  const HeatBatch& hb = cs.batch;
  msg.reads = selective_solve_reads(*in_.Hc.factor.symbolic, hb.plan(), cs.read_mark);
  cs.label_support.clear();
  for (int l = 0; l < msg.lanes; ++l) {
    int32_t sv[3];
    double sw[3];
    const int c = surface_point_support(m_, sites_[order_[b * kLanes + l]], sv, sw);
    cs.label_support.insert(cs.label_support.end(), sv, sv + c);
  }
  plan_selective_solve(*in_.H.factor.symbolic, cs.label_support, hb.kept, cs.label_plan, cs.label_pws);
  msg.label_reads = selective_solve_reads(*in_.H.factor.symbolic, cs.label_plan, cs.read_mark);
}

// The centroid of every lane's cell from the batch's solution: its hottest vertex,
// refined by the quadratic fit (heat_centroid.hpp); empty cells keep their site.
void LloydLoop::refine_centroids(CentroidScratch& cs, CentroidMsg& msg) {
  const HeatBatch& hb = cs.batch;
  const int32_t cnt = hb.count();
  int32_t best[kLanes];
  hottest_vertices(hb, best);
  // Positions of the kept vertices in the solution (localized): the fits read
  // their rings through it (-1 = not kept, heat zero).
  const std::span<int32_t> pos = local_ && opt_.refine ? cs.batch.vertex_map(n_) : std::span<int32_t>();
  if (!pos.empty())
    for (int32_t k = 0; k < cnt; ++k) pos[hb.id(k)] = k;
  for (int l = 0; l < msg.lanes; ++l) {
    const int32_t c = msg.cells[l];
    if (cells_.offsets[c + 1] == cells_.offsets[c]) {
      msg.result[l].hottest = -1;  // empty cell: the site stays
      continue;
    }
    if (!opt_.refine) {
      msg.result[l].hottest = best[l];
      msg.result[l].point = vertex_point(best[l]);
    } else if (local_) {
      msg.result[l] = refine_heat_maximum(m_, in_.geo, hb.values, pos, l, best[l], opt_.fit_rings, opt_.fit_sigma);
    } else {
      for (int32_t k = 0; k < cnt; ++k) cs.dense[k] = hb.values[static_cast<size_t>(k) * kLanes + l];
      msg.result[l] = refine_heat_maximum(m_, in_.geo, cs.dense, best[l], opt_.fit_rings, opt_.fit_sigma);
    }
  }
  if (!pos.empty())
    for (int32_t k = 0; k < cnt; ++k) pos[hb.id(k)] = -1;
  if (!local_) std::fill(cs.dense.begin(), cs.dense.end(), 0.0);
}

// Batch b of 8 cells (runs of 8 in order_): sources, kept set (localized), one
// 8-lane solve, centroids.
std::shared_ptr<CentroidMsg> LloydLoop::solve_centroid_batch(int32_t b,
                                                             std::span<const std::array<double, 3>> before) {
  CentroidScratch& cs = cscratch_.local();
  if (!local_ && cs.dense.size() != static_cast<size_t>(n_)) cs.dense.assign(n_, 0.0);
  auto msg = std::make_shared<CentroidMsg>();
  HeatBatch& hb = cs.batch;
  hb.clear_sources();
  hb.kept.clear();
  cs.cells.clear();
  msg->lanes = std::min(kLanes, ns_ - b * kLanes);
  msg->batch = b;
  for (int l = 0; l < msg->lanes; ++l) {
    const int32_t c = order_[b * kLanes + l];
    msg->cells[l] = c;
    add_cell_source(cs, *msg, l, c, before[c]);
    if (local_) append_two_ring_cells(cells_, c, cs.cells);
  }
  if (local_) {
    cells_to_vertices(cells_, cs.cells, hb.kept);  // the next labels' set of this batch too (batch_kept)
  }
  const double c0 = thread_cpu_seconds();
  solve_heat_batch(in_.Hc, hb);
  msg->solve_cpu_s = thread_cpu_seconds() - c0;
  if (opt_.count_reads && local_) count_batch_reads(cs, *msg, b);
  msg->kept = hb.count();
  refine_centroids(cs, *msg);
  return msg;
}

void LloydLoop::store(const CentroidMsg& msg, CentroidSlots& slots) {  // one slot per cell
  for (int l = 0; l < msg.lanes; ++l) {
    slots.cent[msg.cells[l]] = msg.result[l];
    slots.cell_energy[msg.cells[l]] = msg.energy[l];
    slots.has[msg.cells[l]] = 1;
    if (msg.result[l].hottest >= 0)
      slots.bias[msg.cells[l]] = tangential_distance(m_, in_.geo, msg.result[l].point, msg.area_centroid[l]);
  }
  slots.fallback += msg.fallback;  // integer: order-independent
  kept_fraction_[slots.kept_base + msg.batch] = static_cast<double>(msg.kept) / n_;
  slots.centroid_reads[msg.batch] = msg.reads;
  r_.centroid_solve_cpu_s += msg.solve_cpu_s;
  slots.label_reads[msg.batch] = msg.label_reads;
}

// Read fractions (count_reads), the CVT energy and the centroid bias of the iteration.
void LloydLoop::record_statistics(CentroidSlots& slots, int32_t nbatch) {
  if (opt_.count_reads && local_) {  // batch order: deterministic sums
    const double full = 2.0 * static_cast<double>(full_entries_);
    for (int32_t b = 0; b < nbatch; ++b) {
      centroid_read_sum_ += static_cast<double>(slots.centroid_reads[b]) / full;
      label_read_sum_ += static_cast<double>(slots.label_reads[b]) / full;
    }
    read_batches_ += nbatch;
  }
  r_.energy.push_back(std::accumulate(slots.cell_energy.begin(), slots.cell_energy.end(), 0.0));  // fixed cell order
  std::vector<double>& bias = slots.bias;
  double b2 = 0;
  for (double b : bias) b2 += b * b;  // fixed cell order
  r_.centroid_bias.push_back(std::sqrt(b2 / ns_) / in_.h_r3);
  std::nth_element(bias.begin(), bias.begin() + ns_ / 2, bias.end());
  r_.centroid_bias_median.push_back(bias[ns_ / 2] / in_.h_r3);
}

// The sites move to their cells' centroids (empty cells keep theirs); RMS move.
void LloydLoop::move_sites(const CentroidSlots& slots, std::span<const std::array<double, 3>> before) {
  for (int32_t s = 0; s < ns_; ++s) {  // fixed cell order
    if (!slots.has[s]) fail(ErrorCode::Numerical, "cvt: cell " + std::to_string(s) + " got no centroid");
    if (slots.cent[s].hottest < 0) {
      ++r_.empty_cells;
      continue;
    }
    sites_[s] = slots.cent[s].point;
  }
  double mv = 0;
  for (int32_t s = 0; s < ns_; ++s) {
    const auto p = surface_point_position(m_, sites_[s]);
    mv += (p[0] - before[s][0]) * (p[0] - before[s][0]) + (p[1] - before[s][1]) * (p[1] - before[s][1]) +
          (p[2] - before[s][2]) * (p[2] - before[s][2]);
  }
  r_.moved.push_back(std::sqrt(mv / ns_) / in_.h_r3);
}

void LloydLoop::iterate(int32_t it) {
  ctx_.check_cancel();
  BatchStopwatch isw;
  labels_ctx_ = step_context(it, 0.0, 0.5);
  labels_of_sites(true);
  BatchStopwatch psw;
  // New batches from the new cells (compact patches of the cell graph).
  order_ = cluster_order(cells_, spatial_order(m_, sites_), kLanes);
  r_.neighborhood_s += psw.lap();
  if (opt_.track_quality) {
    const CvtQuality q = cvt_quality(m_, V_.label, sites_);
    r_.mean_angle.push_back(q.mean_angle_deg);
    r_.min_angle.push_back(q.min_angle_deg);
  }
  std::vector<std::array<double, 3>> before(ns_);
  for (int32_t s = 0; s < ns_; ++s) before[s] = surface_point_position(m_, sites_[s]);
  // Centroids: batches of 8 cells in the sites' spatial order.
  const int32_t nbatch = (ns_ + kLanes - 1) / kLanes;
  CentroidSlots slots = centroid_slots(nbatch);
  psw.lap();
  // Reported batch by batch (~1 s at 416k vertices, 1,000 sites: a C host's chances to cancel).
  run_batch_graph<CentroidMsg>(
      step_context(it, 0.5, 1.0), nbatch, [&](int32_t b) { return solve_centroid_batch(b, before); },
      [&](const std::shared_ptr<CentroidMsg>& msg) { store(*msg, slots); }, "centroids");
  r_.centroids_s += psw.lap();
  r_.fallback_faces += slots.fallback;
  record_statistics(slots, nbatch);
  move_sites(slots, before);
  r_.iter_s.push_back(isw.lap());
  step_context(it, 0.0, 1.0).report(1.0, "lloyd");
}

// After the last iteration: the labels of the final sites, so that `label` and
// `sites` belong together, their split-triangle cell areas and the mean fractions.
void LloydLoop::finish() {
  ctx_.check_cancel();
  BatchStopwatch fsw;
  labels_ctx_ = ctx_.sub(static_cast<double>(std::max(1, opt_.iterations)) / (std::max(1, opt_.iterations) + 1.0), 1.0);
  labels_of_sites(false);
  r_.final_labels_s = fsw.lap();
  r_.label.assign(V_.label.begin(), V_.label.end());
  in_arena([&] {
    // Isotropic: the stars hold the R^3 areas, and the areas alone need no
    // mesh-wide list of loads (~100 MB at 416k vertices).
    const HostVector<double> area = opt_.anisotropy == 0 ? cell_areas(in_.stars, V_, cells_.offsets, cells_.verts)
                                                         : partition_cells(m_, in_.area_r3, V_, ns_).area;
    r_.cell_area.assign(area.begin(), area.end());
  });
  if (opt_.keep_voronoi) {  // for heat_voronoi_add, which reads the labels' heat only
    keep_hottest_only(V_);
    r_.voronoi = std::move(V_);
  }
  r_.sites = std::move(sites_);
  if (read_batches_ > 0) {
    r_.centroid_read_fraction = centroid_read_sum_ / static_cast<double>(read_batches_);
    r_.label_read_fraction = label_read_sum_ / static_cast<double>(read_batches_);
  }
  r_.mean_kept_fraction = kept_fraction_.empty() ? 1.0
                                                 : std::accumulate(kept_fraction_.begin(), kept_fraction_.end(), 0.0) /
                                                       static_cast<double>(kept_fraction_.size());
}

// One run from given initial sites: checks, operators, geometry, first
// neighborhoods, then the Lloyd loop.
LloydResult cvt_lloyd_impl(const Mesh& m, const MeshDerived* given, std::vector<SurfacePoint> sites,
                           const LloydOptions& opt, const RunContext& ctx) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  MeshDerived own;
  const MeshDerived& derived = check_lloyd_input(m, given, sites, opt, own);
  const bool local = opt.solver == LloydOptions::Solver::Local;

  LloydResult r;
  BatchStopwatch sw;
  HostVector<double> area_r3 = face_areas(m);
  // Progress: operators and first neighborhoods, then the iterations and the
  // final labels (LloydLoop), one monotone fraction. The first neighborhoods
  // cost ~1.3 iterations, the final labels about one (docs/shipping.md).
  const double init_share = 1.3 / (std::max(1, opt.iterations) + 2.3);
  const RunContext init_ctx = ctx.sub(0.0, init_share);
  LloydOperators ops;
  prepare_lloyd_operators(m, derived, opt, area_r3, sw, init_ctx.sub(0.0, 0.5), ops);
  // The factorizations' workspaces are freed: not resident through the setup
  // below (the peak of a 416k-vertex run's RSS otherwise).
  release_free_memory();
  const HeatDiffusion& H = *ops.H;
  const HeatDiffusion& Hc = *ops.Hc;
  sw.lap();
  r.factor_s = H.operator_s + H.order_s + H.analyze_s + H.factor_s + ops.Hc_own.factor_s;
  r.h = H.h;
  r.t = H.t;
  r.t_centroid = Hc.t;
  r.factor_bytes = static_cast<int64_t>((H.factor.values.size() + ops.Hc_own.factor.values.size()) * sizeof(double));
  ctx.check_cancel();
  const HostVector<double>& mass_r3 = derived.mass;
  const double h_r3 = derived.h;
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  // Reused per (thread, concurrency): an arena per call leaks inside oneTBB.
  const auto in_arena = [arena_threads = std::max(1, threads)](auto&& f) { run_with_threads(arena_threads, f); };
  r.graph_iterations = graph_iterations_of(opt, m.num_vertices());
  HostVector<int32_t> first;  // init_cells: the sites' Dijkstra cells
  CentroidGeometry geo;
  VertexStars stars;
  // ~0.4 s at 416k vertices: the loops are cancel points (cancel_point.hpp).
  ProgressTicker geometry_ticker(init_ctx.sub(0.45, 0.5), "cvt geometry", 2.0);
  std::optional<CancelScope> scope(std::in_place, geometry_ticker);
  in_arena([&] {
    geometry_beside_graph_start(m, derived, std::move(ops.area_op), r.graph_iterations, geometry_ticker, ctx, sites, geo, stars,
                                first);
  });
  ops.area_op = HostVector<double>();  // in the stars now (isotropic: area_r3 moved there)
  ctx.check_cancel();

  // First neighborhoods: Dijkstra balls of the expected cell radius times init_radius.
  std::vector<std::vector<int32_t>> nb;
  if (local && opt.init_cells) {
    if (first.empty()) first = geodesic_site_cells(m, geo.adj(), sites);
    if (std::find(first.begin(), first.end(), -1) != first.end()) first.clear();  // unreachable vertices: balls
  }
  if (!(local && opt.init_cells)) first.clear();
  if (local && first.empty()) {
    const HostVector<double>& mass3 = derived.mass;
    const double area = std::accumulate(mass3.begin(), mass3.end(), 0.0);
    const double radius = opt.init_radius * std::sqrt(area / (M_PI * ns));
    scope.reset();  // the neighborhoods below run on oneTBB workers
    in_arena([&] { nb = geodesic_neighborhoods(m, geo.adj(), sites, radius, ctx); });
    ctx.check_cancel();
  }
  scope.reset();
  r.init_s = sw.lap();

  const RunContext loop_ctx = ctx.sub(init_share, 1.0);
  LloydOptions heat_opt = opt;  // the heat iterations: what the graph iterations left
  heat_opt.iterations = opt.iterations - r.graph_iterations;
  const LloydInputs in{m, heat_opt, loop_ctx, H, Hc, geo, derived.adjacency, stars, area_r3, mass_r3, h_r3, std::max(1, threads),
                       ops.mass_c};
  LloydLoop loop(in, sites, std::move(nb), r);
  if (!first.empty()) {
    loop.first_cells(first);
    HostVector<int32_t>().swap(first);  // in the loop's batches now: not held through the iterations
    r.init_s += sw.lap();
  }
  for (int32_t it = 0; it < heat_opt.iterations; ++it) {
    loop.iterate(it);
    const std::vector<double>& e = r.energy;  // stopping rule (cvt_lloyd.hpp stop_energy)
    if (opt.stop_energy > 0 && e.size() >= 2 && e[e.size() - 2] - e.back() < opt.stop_energy * e.back()) break;
  }
  loop.finish();  // (the fits' face lists stay through it: the stars borrow them)
  return r;
}

LloydResult cvt_lloyd_random(const Mesh& m, const MeshDerived* given, const LloydOptions& opt, const RunContext& ctx) {
  if (opt.sites < 1) fail(ErrorCode::BadUsage, "cvt: at least one site");
  if (!m.is_triangle_mesh() || m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": cvt needs a triangle mesh");
  if (opt.sites > m.num_vertices())
    fail(ErrorCode::BadUsage, "cvt: " + std::to_string(opt.sites) + " sites but only " +
                                  std::to_string(m.num_vertices()) + " vertices (cells cannot be smaller than a vertex)");
  BatchStopwatch sw;
  std::vector<SurfacePoint> init = random_surface_points(m, opt.sites, opt.seed);
  give_every_component_a_site(m, given, init);
  const double seed_s = sw.lap();
  LloydResult r = cvt_lloyd_impl(m, given, std::move(init), opt, ctx);
  r.init_s += seed_s;
  return r;
}

}  // namespace

LloydResult cvt_lloyd(const Mesh& m, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_random(m, nullptr, opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_random(m, &d, opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, std::vector<SurfacePoint> sites, const LloydOptions& opt, const RunContext& ctx) {
  return cvt_lloyd_impl(m, nullptr, std::move(sites), opt, ctx);
}
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, std::vector<SurfacePoint> sites, const LloydOptions& opt,
                      const RunContext& ctx) {
  return cvt_lloyd_impl(m, &d, std::move(sites), opt, ctx);
}

}  // namespace locus
