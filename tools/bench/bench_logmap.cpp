// `locus-bench logmap MESH`: the heat log map (thesis §6.5-6.7) localized with
// exact subset solves, against the same map with full solves and against the
// Dijkstra-based discrete exponential map (DEM), on the same centers and the
// same patches, alternating the contenders within each query so that machine
// noise hits all alike (DESIGN.md "Measuring"). Patches are geodesic disks
// (Dijkstra in graph metric) of round(fraction * n) vertices around seeded
// random centers. Reported per fraction: medians of the query times, the
// ratios full / local and DEM / local, flipped triangles, how far the localized
// map is from the full one (distance: the effect of the Poisson right-hand side
// on the patch only; angle: must be ~0, the heat values are the same), and the
// crossover: the smallest listed fraction from which on the localized heat map
// is faster than DEM. Times are wall-clock medians; the *_cpu_s fields are
// medians of the thread CPU time (robust when other processes load the
// machine), with their own crossover (crossover_fraction_cpu).
//
// The accuracy experiments on analytic surfaces are `logmap-accuracy`
// (bench_logmap_accuracy.cpp) and `geodesic-accuracy` (bench_geodesic_accuracy.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "locus/error.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "tools/bench/bench_centers.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/bench/map_errors.hpp"
#include "tools/bench/stream_bandwidth.hpp"
#include "tools/bench/logmap_choices.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;

std::vector<double> parse_list(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !(v > 0) || v > 1)
      fail(ErrorCode::BadUsage, "--fractions: '" + item + "' is not a number in (0, 1]");
    out.push_back(v);
  }
  if (out.empty()) fail(ErrorCode::BadUsage, "--fractions is empty");
  std::sort(out.begin(), out.end());
  return out;
}

struct TimingOptions {
  std::string fractions = "0.01,0.02,0.05,0.1,0.2";
  int queries = 10;
  double t_factor = HeatGeodesicOptions{}.t_factor;
  bool no_full = false;
  std::string angle = "auto";
  std::string lattice = "default";
  std::string recenter = "default";
};

// The samples of one patch size, over every center.
struct FractionSamples {
  std::vector<double> t_local, t_full, t_dem, t_patch, c_local, c_full, c_dem;
  std::vector<double> mb_heat_read, mb_heat_distinct, mb_poisson_read, mb_poisson_distinct, mb_distinct;
  std::vector<double> ph_region, ph_center, ph_plan, ph_heat, ph_distance, ph_poisson, ph_angles;
  double max_dd = 0, max_da = 0, sum_dd = 0, radius = 0;
  int64_t flipped_heat = 0, flipped_dem = 0, cnt = 0;
  int32_t max_sources = 0, two_ring_centers = 0;
};

// The contenders on one mesh, with the workspaces their queries share.
struct TimingRun {
  TimingRun(const Mesh& mesh, const TimingOptions& options, const HeatLogMap& h, const DemLogMap& d,
            const std::vector<int32_t>& c, const StreamBandwidth& s)
      : to(options), heat(h), dem(d), grower(prepare_patch_grower(mesh)), centers(c), stream(s),
        n(mesh.num_vertices()), patch(n), dem_patch(n), du(n), dv(n) {}

  FractionSamples sample(int32_t count, const RunContext& ctx);
  void sample_center(int32_t c, int32_t count, FractionSamples& fs);
  Json row(double f, int32_t count, const FractionSamples& fs) const;

  const TimingOptions& to;
  const HeatLogMap& heat;
  const DemLogMap& dem;
  const PatchGrower grower;  // the patches: geodesic disks
  const std::vector<int32_t>& centers;
  const StreamBandwidth& stream;
  const int32_t n;
  LogMapWorkspace lws;
  DemWorkspace dws;
  PatchWorkspace pws;
  std::vector<int32_t> patch, dem_patch, scratch;
  Maps local, full;
  std::vector<double> du, dv;
};

FractionSamples TimingRun::sample(int32_t count, const RunContext& ctx) {
  FractionSamples fs;
  for (int32_t c : centers) {
    ctx.check_cancel();
    sample_center(c, count, fs);
  }
  return fs;
}

// One center: the localized query (with its factor traffic and phases), the
// full one, DEM, and the localized map's distance from the full one.
void TimingRun::sample_center(int32_t c, int32_t count, FractionSamples& fs) {
  Stopwatch sw;
  grow_patch_vertices(grower, c, geodesic_disk(count), pws, patch);
  const int32_t k = static_cast<int32_t>(patch.size());
  fs.t_patch.push_back(sw.seconds());
  const std::span<const int32_t> P(patch.data(), k);
  local.resize(k);
  full.resize(k);
  double c0 = thread_cpu_seconds();
  sw.restart();
  const LogMapStats st = heat.query(c, P, local.out(), lws);
  fs.t_local.push_back(sw.seconds());
  fs.c_local.push_back(thread_cpu_seconds() - c0);
  fs.max_sources = std::max(fs.max_sources, st.sources);
  {
    // Factor bytes of this query's two exact solves (the wide heat solve
    // makes st.passes passes over its plan; the Poisson solve one).
    const PlanTraffic th = plan_traffic(*heat.geodesic().heat_factor().symbolic, lws.plan);
    const PlanTraffic tp = plan_traffic(*heat.geodesic().poisson_factor().symbolic, lws.geo.poisson_plan);
    const double mb = 1e-6;
    fs.mb_heat_read.push_back(mb * th.read_bytes() * st.passes);
    fs.mb_heat_distinct.push_back(mb * th.distinct_bytes);
    fs.mb_poisson_read.push_back(mb * tp.read_bytes());
    fs.mb_poisson_distinct.push_back(mb * tp.distinct_bytes);
    fs.mb_distinct.push_back(mb * (th.distinct_bytes + tp.distinct_bytes));
  }
  fs.ph_region.push_back(st.region_s);
  fs.ph_center.push_back(st.center_s);
  fs.ph_plan.push_back(st.plan_s);
  fs.ph_heat.push_back(st.heat_s);
  fs.ph_distance.push_back(st.distance_s);
  fs.ph_poisson.push_back(st.poisson_s);
  fs.ph_angles.push_back(st.angles_s);
  fs.two_ring_centers += st.two_ring;
  if (!to.no_full) {
    c0 = thread_cpu_seconds();
    sw.restart();
    heat.query_full(c, P, full.out(), lws);
    fs.t_full.push_back(sw.seconds());
    fs.c_full.push_back(thread_cpu_seconds() - c0);
  }
  c0 = thread_cpu_seconds();
  sw.restart();
  const int32_t kd = dem.query(c, count, std::numeric_limits<double>::infinity(), dem_patch, du, dv, dws);
  fs.t_dem.push_back(sw.seconds());
  fs.c_dem.push_back(thread_cpu_seconds() - c0);
  fs.flipped_heat += count_flipped_triangles(heat.geodesic().gradients(), P, local.u, local.v, scratch);
  fs.flipped_dem += count_flipped_triangles(heat.geodesic().gradients(), std::span<const int32_t>(dem_patch.data(), kd),
                                            std::span<const double>(du.data(), kd),
                                            std::span<const double>(dv.data(), kd), scratch);
  double r = 0;
  for (int32_t p = 0; p < k; ++p) r = std::max(r, local.d[p]);
  fs.radius += r / centers.size();
  if (!to.no_full)
    for (int32_t p = 0; p < k; ++p) {
      const double dd = std::abs(local.d[p] - full.d[p]);
      fs.max_dd = std::max(fs.max_dd, dd / std::max(r, 1e-300));
      fs.sum_dd += dd / std::max(r, 1e-300);
      if (patch[p] != c) fs.max_da = std::max(fs.max_da, std::abs(wrap(local.a[p] - full.a[p])));
      ++fs.cnt;
    }
}

// The report row of one patch size: medians, ratios, phases, factor traffic.
Json TimingRun::row(double f, int32_t count, const FractionSamples& fs) const {
  const double ml = cli::median(fs.t_local), md = cli::median(fs.t_dem);
  Json row{{"fraction", f}, {"patch_size", count}, {"queries", centers.size()}};
  row["heat_local_s"] = ml;
  if (!to.no_full) {
    row["heat_full_s"] = cli::median(fs.t_full);
    row["full_over_local"] = cli::median(fs.t_full) / ml;
  }
  row["dem_s"] = md;
  row["dem_over_local"] = md / ml;
  // Thread CPU time medians (the machine may be loaded by other processes).
  row["heat_local_cpu_s"] = cli::median(fs.c_local);
  row["dem_cpu_s"] = cli::median(fs.c_dem);
  row["dem_over_local_cpu"] = cli::median(fs.c_dem) / cli::median(fs.c_local);
  if (!to.no_full) {
    row["heat_full_cpu_s"] = cli::median(fs.c_full);
    row["full_over_local_cpu"] = cli::median(fs.c_full) / cli::median(fs.c_local);
  }
  row["patch_select_s"] = cli::median(fs.t_patch);  // the DEM's Dijkstra disk, outside every timed query
  // Localized query by phase (medians of thread CPU time; they need not add up to heat_local_cpu_s exactly).
  row["phases_s"] = Json{{"region", cli::median(fs.ph_region)},     {"center", cli::median(fs.ph_center)},
                         {"heat_plan", cli::median(fs.ph_plan)},     {"heat_solve", cli::median(fs.ph_heat)},
                         {"distance", cli::median(fs.ph_distance)}, {"poisson", cli::median(fs.ph_poisson)},
                         {"angles", cli::median(fs.ph_angles)}};
  // Factor traffic of the two exact solves (medians, MB = 1e6 bytes) and the
  // time streaming the distinct bytes once would take at the best measured
  // single-core read rate: no exact-solve query can be faster than that.
  const double floor_s = cli::median(fs.mb_distinct) * 1e6 / stream.best_bytes_per_s;
  row["factor_traffic_mb"] = Json{{"heat_read", cli::median(fs.mb_heat_read)},
                                  {"heat_distinct", cli::median(fs.mb_heat_distinct)},
                                  {"poisson_read", cli::median(fs.mb_poisson_read)},
                                  {"poisson_distinct", cli::median(fs.mb_poisson_distinct)},
                                  {"distinct", cli::median(fs.mb_distinct)}};
  row["stream_floor_s"] = floor_s;
  row["dem_over_floor"] = md / floor_s;
  row["max_sources"] = fs.max_sources;
  row["two_ring_centers"] = fs.two_ring_centers;
  row["mean_patch_radius"] = fs.radius;
  row["flipped_triangles_heat"] = fs.flipped_heat;
  row["flipped_triangles_dem"] = fs.flipped_dem;
  if (!to.no_full && fs.cnt > 0) {
    row["local_vs_full_distance_max_rel"] = fs.max_dd;  // relative to the patch radius
    row["local_vs_full_distance_mean_rel"] = fs.sum_dd / fs.cnt;
    row["local_vs_full_angle_max"] = fs.max_da;
  }
  return row;
}

// The smallest listed fraction from which on the localized map wins (-1: none).
double crossover(const std::vector<double>& fractions, const std::vector<double>& wins) {
  double from = -1;
  for (size_t q = fractions.size(); q-- > 0;) {
    if (wins[q] == 0) break;
    from = fractions[q];
  }
  return from;
}

int run_logmap(const cli::CommonOptions& opt, const TimingOptions& to, const RunContext& ctx) {
  const std::vector<double> fractions = parse_list(to.fractions);
  if (to.queries < 1) fail(ErrorCode::BadUsage, "--queries must be at least 1");
  cli::Input in = cli::load_input(opt, ctx);
  const int32_t n = in.mesh.num_vertices();
  Stopwatch sw;
  LogMapOptions lo;
  lo.geodesic.t_factor = to.t_factor;
  lo.angle = cli::parse_logmap_angle(to.angle);
  if (const auto l = cli::parse_logmap_lattice(to.lattice)) lo.lattice = *l;
  if (const auto r = cli::parse_logmap_recenter(to.recenter)) lo.recenter = *r;
  const HeatLogMap heat(in.mesh, lo, ctx);
  const double precompute_s = sw.seconds();
  sw.restart();
  const DemLogMap dem(in.mesh);
  const double dem_prepare_s = sw.seconds();
  const std::vector<int32_t> centers = pick_centers(n, to.queries, opt.seed);
  // This machine's single-core streaming read rate: with the factor bytes a
  // query's exact solves read (plan_traffic), a floor on their time.
  const StreamBandwidth stream = measure_stream_read();
  TimingRun run(in.mesh, to, heat, dem, centers, stream);
  Json rows = Json::array();
  std::vector<double> local_wins, local_wins_cpu;
  for (double f : fractions) {
    const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(f * n)));
    const FractionSamples fs = run.sample(count, ctx);
    rows.push_back(run.row(f, count, fs));
    const double ml = cli::median(fs.t_local), md = cli::median(fs.t_dem);
    local_wins.push_back(ml < md ? 1.0 : 0.0);
    local_wins_cpu.push_back(cli::median(fs.c_local) < cli::median(fs.c_dem) ? 1.0 : 0.0);
    cli::log("logmap: fraction " + cli::format_number(f) + ": local " + cli::format_number(ml) + " s, DEM " +
             cli::format_number(md) + " s" +
             (to.no_full ? std::string() : ", full " + cli::format_number(cli::median(fs.t_full)) + " s"));
  }
  const double crossover_wall = crossover(fractions, local_wins), crossover_cpu = crossover(fractions, local_wins_cpu);
  Json j{{"command", "logmap"}, {"input", cli::input_json(opt, in)}};
  j["n"] = n;
  j["t_factor"] = to.t_factor;
  j["angle"] = to.angle;
  j["lattice"] = to.lattice;
  j["recenter"] = to.recenter;
  j["h"] = heat.geodesic().mean_edge_length();
  j["precompute_s"] = precompute_s;
  j["dem_prepare_s"] = dem_prepare_s;
  j["queries"] = centers.size();
  j["stream_read_gbs"] = Json{{"best", stream.best_bytes_per_s * 1e-9}, {"median", stream.median_bytes_per_s * 1e-9}};
  j["rows"] = rows;
  j["crossover_fraction"] = crossover_wall < 0 ? Json(nullptr) : Json(crossover_wall);
  j["crossover_fraction_cpu"] = crossover_cpu < 0 ? Json(nullptr) : Json(crossover_cpu);
  cli::emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": n " << n << ", precompute " << precompute_s << " s, " << centers.size()
       << " centers, medians\n";
    for (const Json& r : rows) {
      os << "  fraction " << r["fraction"] << " (" << r["patch_size"] << " vertices): local " << r["heat_local_s"]
         << " s, DEM " << r["dem_s"] << " s (DEM/local " << r["dem_over_local"] << ")";
      if (r.contains("heat_full_s")) os << ", full " << r["heat_full_s"] << " s (full/local " << r["full_over_local"] << ")";
      os << "\n";
    }
    os << "  crossover fraction (local faster than DEM from here on): " << j["crossover_fraction"] << "\n";
  });
  return 0;
}

}  // namespace

void register_logmap_bench(cli::CommandTable& table) {
  auto to = std::make_shared<TimingOptions>();
  CLI::App* app = table.add("logmap", "heat log map: localized vs full solves vs DEM, medians and crossover",
                            [to](const cli::CommonOptions& o, const RunContext& ctx) { return run_logmap(o, *to, ctx); });
  app->add_option("--fractions", to->fractions, "Patch sizes as fractions of the vertex count, comma-separated");
  app->add_option("--queries", to->queries, "Random centers (seeded by --seed), default 10");
  app->add_option("--t-factor", to->t_factor, "t = c h^2 (default: the library's, HeatGeodesicOptions::t_factor)");
  app->add_flag("--no-full", to->no_full, "Skip the full-solve variant");
  app->add_option("--angle", to->angle, "Angle estimator: auto (default), log, two-ring, average");
  app->add_option("--lattice", to->lattice, "Lattice correction: none, star, ring, path (default: the library's)");
  app->add_option("--recenter,--recentre", to->recenter, "Recenter the gradients: on, off (default: the library's)");
}

}  // namespace locus::bench
