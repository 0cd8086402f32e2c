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
// `locus-bench logmap-accuracy SPEC`: the accuracy experiment of thesis §6.7
// (Table 6.8.1) on analytic surfaces, SPEC one of
//   icosphere:L        unit icosphere, level L (7: ~164k vertices, h ~ 0.0094)
//   random-sphere:N    convex hull of N random unit vectors (irregular)
//   cube-sphere:N      cube with N x N quads per face projected on the unit sphere
//                      (polygons: the polygon log map, full solves); cube-sphere-tri:N triangulated
//   bump:R             z = exp(-(x^2 + y^2) / sigma^2) over the disk of radius 1.5
//                      (R rings, h ~ 1.5 / R), center at the top
// Patch: the vertices within geodesic distance --radius (exact) of the center.
// Errors: E_d = mean |d - d_exact|, E_a = mean |angle - angle_exact - delta|
// (wrapped) with delta the best global rotation (circular mean of the
// differences), both over the patch without the center. Exact values: on the
// sphere d = acos(p_c . p_j) and the azimuth of p_j in the tangent plane of p_c;
// on the bump the azimuth atan2(y, x) and the arc length of the radial profile
// by Simpson quadrature. Heat (localized, both angle estimators and both
// Poisson right-hand sides), heat with full solves, and DEM; under "variants"
// every angle estimator x lattice correction x recenter (pipelines/include/locus/pipelines/geodesic/logmap.hpp)
// with the mean, the worst center and the per-center E_a. --center-ids picks
// the centers (e.g. 0,13: an icosahedron corner and an edge midpoint), --dump
// writes per-vertex values of one variant (--dump-variant).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <sstream>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/bench/stream_bandwidth.hpp"
#include "tools/cli/logmap_choices.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;
constexpr double kPi = 3.14159265358979323846;

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

// Distinct seeded centers (splitmix64 through cli::random_vector).
std::vector<int32_t> pick_centers(int32_t n, int q, uint64_t seed) {
  const std::vector<double> r = cli::random_vector(static_cast<size_t>(q) * 4, seed);
  std::vector<int32_t> c;
  for (double x : r) {
    const int32_t v = std::min(n - 1, static_cast<int32_t>((x + 1.0) * 0.5 * n));
    if (std::find(c.begin(), c.end(), v) == c.end()) c.push_back(v);
    if (static_cast<int>(c.size()) == q) break;
  }
  return c;
}

double wrap(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

struct Maps {  // one map's output over a patch
  std::vector<double> d, a, u, v;
  void resize(size_t k) {
    d.resize(k);
    a.resize(k);
    u.resize(k);
    v.resize(k);
  }
  LogMapOutput out() { return {d, a, u, v}; }
};

// ---------------------------------------------------------------- timing ----

struct TimingOptions {
  std::string fractions = "0.01,0.02,0.05,0.1,0.2";
  int queries = 10;
  double t_factor = HeatGeodesicOptions{}.t_factor;
  bool no_full = false;
  std::string angle = "auto";
  std::string lattice = "default";
  std::string recenter = "default";
};

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
  const PatchGrower grower = prepare_patch_grower(in.mesh);  // the patches: geodesic disks
  const std::vector<int32_t> centers = pick_centers(n, to.queries, opt.seed);
  // This machine's single-core streaming read rate: with the factor bytes a
  // query's exact solves read (plan_traffic), a floor on their time.
  const StreamBandwidth stream = measure_stream_read();

  LogMapWorkspace lws;
  DemWorkspace dws;
  PatchWorkspace pws;
  std::vector<int32_t> patch(n), dem_patch(n), scratch;
  Maps local, full;
  std::vector<double> du(n), dv(n);
  Json rows = Json::array();
  double crossover = -1;
  std::vector<double> local_wins, local_wins_cpu;
  for (double f : fractions) {
    const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(f * n)));
    std::vector<double> t_local, t_full, t_dem, t_patch, c_local, c_full, c_dem;
    std::vector<double> mb_heat_read, mb_heat_distinct, mb_poisson_read, mb_poisson_distinct, mb_distinct;
    std::vector<double> ph_region, ph_center, ph_plan, ph_heat, ph_distance, ph_poisson, ph_angles;
    double max_dd = 0, max_da = 0, sum_dd = 0, radius = 0;
    int64_t flipped_heat = 0, flipped_dem = 0, cnt = 0;
    int32_t max_sources = 0, two_ring_centers = 0;
    for (int32_t c : centers) {
      ctx.check_cancel();
      sw.restart();
      grow_patch_vertices(grower, c, geodesic_disk(count), pws, patch);
      const int32_t k = static_cast<int32_t>(patch.size());
      t_patch.push_back(sw.seconds());
      const std::span<const int32_t> P(patch.data(), k);
      local.resize(k);
      full.resize(k);
      double c0 = thread_cpu_seconds();
      sw.restart();
      const LogMapStats st = heat.query(c, P, local.out(), lws);
      t_local.push_back(sw.seconds());
      c_local.push_back(thread_cpu_seconds() - c0);
      max_sources = std::max(max_sources, st.sources);
      {
        // Factor bytes of this query's two exact solves (the wide heat solve
        // makes st.passes passes over its plan; the Poisson solve one).
        const PlanTraffic th = plan_traffic(*heat.geodesic().heat_factor().symbolic, lws.plan);
        const PlanTraffic tp = plan_traffic(*heat.geodesic().poisson_factor().symbolic, lws.geo.poisson_plan);
        const double mb = 1e-6;
        mb_heat_read.push_back(mb * th.read_bytes() * st.passes);
        mb_heat_distinct.push_back(mb * th.distinct_bytes);
        mb_poisson_read.push_back(mb * tp.read_bytes());
        mb_poisson_distinct.push_back(mb * tp.distinct_bytes);
        mb_distinct.push_back(mb * (th.distinct_bytes + tp.distinct_bytes));
      }
      ph_region.push_back(st.region_s);
      ph_center.push_back(st.center_s);
      ph_plan.push_back(st.plan_s);
      ph_heat.push_back(st.heat_s);
      ph_distance.push_back(st.distance_s);
      ph_poisson.push_back(st.poisson_s);
      ph_angles.push_back(st.angles_s);
      two_ring_centers += st.two_ring;
      if (!to.no_full) {
        c0 = thread_cpu_seconds();
        sw.restart();
        heat.query_full(c, P, full.out(), lws);
        t_full.push_back(sw.seconds());
        c_full.push_back(thread_cpu_seconds() - c0);
      }
      c0 = thread_cpu_seconds();
      sw.restart();
      const int32_t kd = dem.query(c, count, std::numeric_limits<double>::infinity(), dem_patch, du, dv, dws);
      t_dem.push_back(sw.seconds());
      c_dem.push_back(thread_cpu_seconds() - c0);
      flipped_heat += count_flipped_triangles(heat.geodesic().gradients(), P, local.u, local.v, scratch);
      flipped_dem += count_flipped_triangles(heat.geodesic().gradients(), std::span<const int32_t>(dem_patch.data(), kd),
                                             std::span<const double>(du.data(), kd),
                                             std::span<const double>(dv.data(), kd), scratch);
      double r = 0;
      for (int32_t p = 0; p < k; ++p) r = std::max(r, local.d[p]);
      radius += r / centers.size();
      if (!to.no_full)
        for (int32_t p = 0; p < k; ++p) {
          const double dd = std::abs(local.d[p] - full.d[p]);
          max_dd = std::max(max_dd, dd / std::max(r, 1e-300));
          sum_dd += dd / std::max(r, 1e-300);
          if (patch[p] != c) max_da = std::max(max_da, std::abs(wrap(local.a[p] - full.a[p])));
          ++cnt;
        }
    }
    const double ml = cli::median(t_local), md = cli::median(t_dem);
    Json row{{"fraction", f}, {"patch_size", count}, {"queries", centers.size()}};
    row["heat_local_s"] = ml;
    if (!to.no_full) {
      row["heat_full_s"] = cli::median(t_full);
      row["full_over_local"] = cli::median(t_full) / ml;
    }
    row["dem_s"] = md;
    row["dem_over_local"] = md / ml;
    // Thread CPU time medians (the machine may be loaded by other processes).
    row["heat_local_cpu_s"] = cli::median(c_local);
    row["dem_cpu_s"] = cli::median(c_dem);
    row["dem_over_local_cpu"] = cli::median(c_dem) / cli::median(c_local);
    if (!to.no_full) {
      row["heat_full_cpu_s"] = cli::median(c_full);
      row["full_over_local_cpu"] = cli::median(c_full) / cli::median(c_local);
    }
    row["patch_select_s"] = cli::median(t_patch);  // the DEM's Dijkstra disk, outside every timed query
    // Localized query by phase (medians of thread CPU time; they need not add up to heat_local_cpu_s exactly).
    row["phases_s"] = Json{{"region", cli::median(ph_region)},     {"center", cli::median(ph_center)},
                           {"heat_plan", cli::median(ph_plan)},     {"heat_solve", cli::median(ph_heat)},
                           {"distance", cli::median(ph_distance)}, {"poisson", cli::median(ph_poisson)},
                           {"angles", cli::median(ph_angles)}};
    // Factor traffic of the two exact solves (medians, MB = 1e6 bytes) and the
    // time streaming the distinct bytes once would take at the best measured
    // single-core read rate: no exact-solve query can be faster than that.
    const double floor_s = cli::median(mb_distinct) * 1e6 / stream.best_bytes_per_s;
    row["factor_traffic_mb"] = Json{{"heat_read", cli::median(mb_heat_read)},
                                    {"heat_distinct", cli::median(mb_heat_distinct)},
                                    {"poisson_read", cli::median(mb_poisson_read)},
                                    {"poisson_distinct", cli::median(mb_poisson_distinct)},
                                    {"distinct", cli::median(mb_distinct)}};
    row["stream_floor_s"] = floor_s;
    row["dem_over_floor"] = md / floor_s;
    row["max_sources"] = max_sources;
    row["two_ring_centers"] = two_ring_centers;
    row["mean_patch_radius"] = radius;
    row["flipped_triangles_heat"] = flipped_heat;
    row["flipped_triangles_dem"] = flipped_dem;
    if (!to.no_full && cnt > 0) {
      row["local_vs_full_distance_max_rel"] = max_dd;  // relative to the patch radius
      row["local_vs_full_distance_mean_rel"] = sum_dd / cnt;
      row["local_vs_full_angle_max"] = max_da;
    }
    rows.push_back(row);
    local_wins.push_back(ml < md ? 1.0 : 0.0);
    local_wins_cpu.push_back(cli::median(c_local) < cli::median(c_dem) ? 1.0 : 0.0);
    cli::log("logmap: fraction " + cli::format_number(f) + ": local " + cli::format_number(ml) + " s, DEM " +
             cli::format_number(md) + " s" +
             (to.no_full ? std::string() : ", full " + cli::format_number(cli::median(t_full)) + " s"));
  }
  for (size_t q = fractions.size(); q-- > 0;) {
    if (local_wins[q] == 0) break;
    crossover = fractions[q];
  }
  double crossover_cpu = -1;
  for (size_t q = fractions.size(); q-- > 0;) {
    if (local_wins_cpu[q] == 0) break;
    crossover_cpu = fractions[q];
  }
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
  j["crossover_fraction"] = crossover < 0 ? Json(nullptr) : Json(crossover);
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

// -------------------------------------------------------------- accuracy ----

struct Surface {
  Mesh mesh;
  std::string kind;  // "sphere" or "bump"
  double sigma = 0.5;
  std::vector<double> profile_r, profile_s;  // bump: arc length s(r) on a fine grid
  double exact_distance(int32_t c, int32_t j) const {
    if (kind == "sphere") {
      const double d = mesh.x[c] * mesh.x[j] + mesh.y[c] * mesh.y[j] + mesh.z[c] * mesh.z[j];
      const double nc = std::sqrt(mesh.x[c] * mesh.x[c] + mesh.y[c] * mesh.y[c] + mesh.z[c] * mesh.z[c]);
      const double nj = std::sqrt(mesh.x[j] * mesh.x[j] + mesh.y[j] * mesh.y[j] + mesh.z[j] * mesh.z[j]);
      return std::acos(std::clamp(d / (nc * nj), -1.0, 1.0));
    }
    const double r = std::hypot(mesh.x[j], mesh.y[j]);
    const double step = profile_r[1] - profile_r[0];
    const size_t k = std::min(profile_r.size() - 2, static_cast<size_t>(r / step));
    const double w = (r - profile_r[k]) / step;
    return profile_s[k] * (1 - w) + profile_s[k + 1] * w;
  }
};

Surface make_surface(const std::string& spec) {
  const size_t colon = spec.find(':');
  if (colon == std::string::npos) fail(ErrorCode::BadUsage, "accuracy surface '" + spec + "': expected KIND:SIZE");
  const std::string kind = spec.substr(0, colon);
  char* end = nullptr;
  const long size = std::strtol(spec.c_str() + colon + 1, &end, 10);
  if (*end != '\0' || size < 1) fail(ErrorCode::BadUsage, "accuracy surface '" + spec + "': bad size");
  Surface s;
  if (kind == "icosphere") {
    if (size > 9) fail(ErrorCode::BadUsage, "icosphere level at most 9");
    s.mesh = make_icosphere(static_cast<int>(size), 1.0);
    s.kind = "sphere";
  } else if (kind == "random-sphere") {
    s.mesh = make_random_sphere(static_cast<int32_t>(size), 12345);
    s.kind = "sphere";
  } else if (kind == "cube-sphere" || kind == "cube-sphere-tri") {
    if (size > 2000) fail(ErrorCode::BadUsage, "cube-sphere: at most 2000 quads per cube edge");
    s.mesh = make_cube_sphere(static_cast<int32_t>(size), kind == "cube-sphere-tri");
    s.kind = "sphere";
  } else if (kind == "bump") {
    s.mesh = make_disk(static_cast<int32_t>(size));
    s.kind = "bump";
    const double R = 1.5, sig2 = s.sigma * s.sigma;
    for (int32_t i = 0; i < s.mesh.num_vertices(); ++i) {
      s.mesh.x[i] *= R;
      s.mesh.y[i] *= R;
      s.mesh.z[i] = std::exp(-(s.mesh.x[i] * s.mesh.x[i] + s.mesh.y[i] * s.mesh.y[i]) / sig2);
    }
    // s(r) = int_0^r sqrt(1 + f'(p)^2) dp, f' = -2p/sigma^2 exp(-p^2/sigma^2); Simpson per cell.
    const int cells = 200000;
    const double step = 2.2 / cells;
    auto integrand = [&](double p) {
      const double fp = -2 * p / sig2 * std::exp(-p * p / sig2);
      return std::sqrt(1 + fp * fp);
    };
    s.profile_r.resize(cells + 1);
    s.profile_s.resize(cells + 1);
    for (int k = 0; k <= cells; ++k) s.profile_r[k] = k * step;
    for (int k = 0; k < cells; ++k) {
      const double a = k * step;
      s.profile_s[k + 1] =
          s.profile_s[k] + step / 6 * (integrand(a) + 4 * integrand(a + step / 2) + integrand(a + step));
    }
  } else {
    fail(ErrorCode::BadUsage, "accuracy surface kind '" + kind + "': use icosphere, random-sphere, cube-sphere, cube-sphere-tri or bump");
  }
  return s;
}

// Exact azimuth of j around c.
double exact_angle(const Surface& s, int32_t c, int32_t j) {
  const Mesh& m = s.mesh;
  if (s.kind == "bump") return std::atan2(m.y[j] - m.y[c], m.x[j] - m.x[c]);
  const double n[3] = {m.x[c], m.y[c], m.z[c]};
  const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double nn[3] = {n[0] / nl, n[1] / nl, n[2] / nl};
  // Any tangent basis: the rotation is removed by the best global offset.
  double a[3] = {1, 0, 0};
  if (std::abs(nn[0]) > 0.9) a[0] = 0, a[1] = 1;
  const double an = a[0] * nn[0] + a[1] * nn[1] + a[2] * nn[2];
  double b1[3] = {a[0] - an * nn[0], a[1] - an * nn[1], a[2] - an * nn[2]};
  const double bl = std::sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  for (double& x : b1) x /= bl;
  const double b2[3] = {nn[1] * b1[2] - nn[2] * b1[1], nn[2] * b1[0] - nn[0] * b1[2], nn[0] * b1[1] - nn[1] * b1[0]};
  const double p[3] = {m.x[j], m.y[j], m.z[j]};
  return std::atan2(p[0] * b2[0] + p[1] * b2[1] + p[2] * b2[2], p[0] * b1[0] + p[1] * b1[1] + p[2] * b1[2]);
}

struct Errors {
  double ed = 0, ea = 0;
  int64_t count = 0;
};

// Errors by radius band: band k holds the patch vertices whose exact distance
// is in [k, k + 1) * R / bands, R the patch's largest exact distance (the
// outermost band is "the rim"). Sums over every vertex of every center.
struct Bands {
  std::vector<double> ed, ea;
  std::vector<int64_t> count;
  explicit Bands(int k = 10) : ed(k, 0.0), ea(k, 0.0), count(k, 0) {}
  int size() const { return static_cast<int>(ed.size()); }
  double mean_ed(int a, int b) const {  // over bands [a, b)
    double s = 0;
    int64_t c = 0;
    for (int k = a; k < b; ++k) s += ed[k], c += count[k];
    return c > 0 ? s / c : 0.0;
  }
  double mean_ea(int a, int b) const {
    double s = 0;
    int64_t c = 0;
    for (int k = a; k < b; ++k) s += ea[k], c += count[k];
    return c > 0 ? s / c : 0.0;
  }
  Json json() const {
    Json rows = Json::array();
    for (int k = 0; k < size(); ++k)
      rows.push_back(Json{{"from", static_cast<double>(k) / size()}, {"to", static_cast<double>(k + 1) / size()},
                          {"E_d", count[k] > 0 ? ed[k] / count[k] : 0.0},
                          {"E_a", count[k] > 0 ? ea[k] / count[k] : 0.0}, {"vertices", count[k]}});
    const int n = size();
    const double inner = mean_ed(0, n / 2), outer = mean_ed(n - 1, n);
    return Json{{"bands", rows}, {"E_d_inner_half", inner}, {"E_d_outer_band", outer},
                {"E_d_outer_over_inner", inner > 0 ? outer / inner : 0.0}, {"E_a_inner_half", mean_ea(0, n / 2)},
                {"E_a_outer_band", mean_ea(n - 1, n)}};
  }
};

// Mean errors over the patch minus the center; `mapped[p]` false skips p;
// `bands`, when given, also receives every vertex's errors by radius band.
Errors errors_of(const Surface& s, int32_t c, std::span<const int32_t> patch, std::span<const double> d,
                 std::span<const double> a, const std::vector<uint8_t>* mapped = nullptr, Bands* bands = nullptr) {
  double cs = 0, sn = 0;
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == c || (mapped && !(*mapped)[p])) continue;
    const double diff = a[p] - exact_angle(s, c, patch[p]);
    cs += std::cos(diff);
    sn += std::sin(diff);
  }
  const double delta = std::atan2(sn, cs);
  Errors e;
  double rmax = 0;
  if (bands)
    for (int32_t j : patch) rmax = std::max(rmax, s.exact_distance(c, j));
  for (size_t p = 0; p < patch.size(); ++p) {
    if (patch[p] == c || (mapped && !(*mapped)[p])) continue;
    const double r = s.exact_distance(c, patch[p]);
    const double ed = std::abs(d[p] - r), ea = std::abs(wrap(a[p] - exact_angle(s, c, patch[p]) - delta));
    e.ed += ed;
    e.ea += ea;
    ++e.count;
    if (bands && rmax > 0) {
      const int k = std::min(bands->size() - 1, static_cast<int>(r / rmax * bands->size()));
      bands->ed[k] += ed;
      bands->ea[k] += ea;
      ++bands->count[k];
    }
  }
  if (e.count > 0) {
    e.ed /= e.count;
    e.ea /= e.count;
  }
  return e;
}

struct AccuracyOptions {
  int centers = 3;
  double radius = 0.5;
  double t_factor = 0;  // 0: the library's default (triangles: HeatGeodesicOptions, polygons: PolygonHeatGeodesicOptions)
  bool no_full = false;
  bool plain_gradient = false;  // HeatGeodesicOptions::log_heat_gradient = false
  std::string dump;  // CSV of per-vertex exact and computed values of one variant
  std::string dump_variant = "log_none";
  std::string center_ids;  // explicit centers instead of random ones
  std::string lattice = "default";  // the correction of the default (Auto) rows
  std::string recenter = "default";
  double mass_blend = 0.0;
  std::string center_set = "random";  // random, or irregular: vertices of valence != 6 (--centers of them)
  std::string patch_kind = "exact";   // exact: within --radius; graph: the Dijkstra disk of as many vertices (the CLI's)
  bool quick = false;                 // the default map, full solves and DEM only (no estimator variants)
  int bands = 10;                     // radius bands of the default map's errors
  std::string save_surface;           // write the generated surface (e.g. .off) for the CLI
};

// The centers: --center-ids, else the bump's top, else --centers random ones
// (or, with --center-set irregular, --centers vertices of valence != 6 spread
// evenly over the ids: on icospheres the icosahedron's 12 corners, valence 5).
std::vector<int32_t> accuracy_centers(const Surface& s, const AccuracyOptions& ao, uint64_t seed) {
  const int32_t n = s.mesh.num_vertices();
  std::vector<int32_t> centers;
  if (!ao.center_ids.empty()) {
    std::stringstream ss(ao.center_ids);
    std::string item;
    while (std::getline(ss, item, ',')) {
      char* end = nullptr;
      const long v = std::strtol(item.c_str(), &end, 10);
      if (end == item.c_str() || *end != '\0' || v < 0 || v >= n)
        fail(ErrorCode::BadUsage, "--center-ids: '" + item + "' is not a vertex id (0.." + std::to_string(n - 1) + ")");
      centers.push_back(static_cast<int32_t>(v));
    }
    return centers;
  }
  if (s.kind == "bump") return {0};
  if (ao.center_set == "random") return pick_centers(n, ao.centers, seed);
  if (ao.center_set != "irregular") fail(ErrorCode::BadUsage, "--center-set must be random or irregular");
  std::vector<int32_t> valence(static_cast<size_t>(n), 0), odd;
  for (int32_t f = 0; f < s.mesh.num_faces(); ++f) ++valence[s.mesh.f0[f]], ++valence[s.mesh.f1[f]], ++valence[s.mesh.f2[f]];
  for (int32_t v = 0; v < n; ++v)
    if (valence[v] != 6) odd.push_back(v);
  const size_t want = std::min(odd.size(), static_cast<size_t>(std::max(ao.centers, 1)));
  for (size_t k = 0; k < want; ++k) centers.push_back(odd[k * odd.size() / want]);
  if (centers.empty()) fail(ErrorCode::BadUsage, "--center-set irregular: every vertex has valence 6");
  return centers;
}

// Polygon meshes (cube-sphere:N): the polygon log map (full solves), E_d / E_a
// per center and by radius band, flipped polygons.
int run_polygon_accuracy(const cli::CommonOptions& opt, const AccuracyOptions& ao, const Surface& s,
                         const RunContext& ctx) {
  PolygonHeatGeodesicOptions po;
  if (ao.t_factor > 0) po.t_factor = ao.t_factor;
  Stopwatch sw;
  const PolygonLogMap lm(s.mesh, po, ctx);
  const double precompute_s = sw.seconds();
  const std::vector<int32_t> centers = accuracy_centers(s, ao, opt.seed);
  const int32_t n = s.mesh.num_vertices();
  std::vector<int32_t> valence(static_cast<size_t>(n), 0);
  for (int32_t v : s.mesh.face_vertices) ++valence[v];
  Bands bands(ao.bands);
  Json per_center = Json::array();
  double ed = 0, ea = 0, query_s = 0;
  int64_t flipped = 0;
  for (int32_t c : centers) {
    ctx.check_cancel();
    std::vector<int32_t> patch{c};
    for (int32_t j = 0; j < n; ++j)
      if (j != c && s.exact_distance(c, j) <= ao.radius) patch.push_back(j);
    Maps m;
    m.resize(patch.size());
    sw.restart();
    lm.query_full(c, patch, m.out());
    query_s += sw.seconds() / centers.size();
    const Errors e = errors_of(s, c, patch, m.d, m.a, nullptr, &bands);
    ed += e.ed / centers.size();
    ea += e.ea / centers.size();
    const int64_t f = count_flipped_polygons(s.mesh, patch, m.u, m.v);
    flipped += f;
    per_center.push_back(Json{{"center", c}, {"valence", valence[c]}, {"patch_size", patch.size()}, {"E_d", e.ed},
                              {"E_a", e.ea}, {"flipped_polygons", f}});
  }
  Json j{{"command", "logmap-accuracy"}, {"surface", opt.mesh_path}, {"polygons", true}};
  j["n"] = n;
  j["h"] = lm.geodesic().mean_edge_length();
  j["t"] = lm.geodesic().time();
  j["t_factor"] = po.t_factor;
  j["radius"] = ao.radius;
  j["centers"] = centers;
  j["heat_full_polygon"] = Json{{"E_d", ed}, {"E_a", ea}};
  j["flipped_polygons"] = flipped;
  j["per_center"] = per_center;
  j["radius_bands_full"] = bands.json();
  j["precompute_s"] = precompute_s;
  j["query_s"] = query_s;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

int run_accuracy(const cli::CommonOptions& opt, const AccuracyOptions& ao, const RunContext& ctx) {
  Stopwatch sw;
  const Surface s = make_surface(opt.mesh_path);
  if (!s.mesh.is_triangle_mesh()) return run_polygon_accuracy(opt, ao, s, ctx);
  const double generate_s = sw.seconds();
  const int32_t n = s.mesh.num_vertices();
  sw.restart();
  LogMapOptions lo;
  if (ao.t_factor > 0) lo.geodesic.t_factor = ao.t_factor;
  lo.geodesic.log_heat_gradient = !ao.plain_gradient;
  if (const auto l = cli::parse_logmap_lattice(ao.lattice)) lo.lattice = *l;
  if (const auto r = cli::parse_logmap_recenter(ao.recenter)) lo.recenter = *r;
  lo.geodesic.mass_blend = ao.mass_blend;
  const HeatLogMap heat(s.mesh, lo, ctx);
  const double precompute_s = sw.seconds();
  const DemLogMap dem(s.mesh);
  const std::vector<int32_t> centers = accuracy_centers(s, ao, opt.seed);
  if (ao.patch_kind != "exact" && ao.patch_kind != "graph") fail(ErrorCode::BadUsage, "--patch must be exact or graph");
  if (ao.bands < 2 || ao.bands > 100) fail(ErrorCode::BadUsage, "--bands must be in 2..100");
  if (!ao.save_surface.empty()) write_mesh(ao.save_surface, s.mesh);
  const PatchGrower grower = ao.patch_kind == "graph" ? prepare_patch_grower(s.mesh) : PatchGrower{};
  PatchWorkspace pws;
  std::vector<int32_t> valence(static_cast<size_t>(n), 0);
  for (int32_t f = 0; f < s.mesh.num_faces(); ++f) ++valence[s.mesh.f0[f]], ++valence[s.mesh.f1[f]], ++valence[s.mesh.f2[f]];
  Bands bands_local(ao.bands), bands_full(ao.bands);
  Json per_center = Json::array();

  // Accumulated means over centers (each center's mean weighs the same) and the worst center.
  struct Acc {
    double ed = 0, ea = 0, ed_worst = 0, ea_worst = 0;
    int32_t worst_center = -1;
    void add(const Errors& e, double w, int32_t c = -1) {
      ed += e.ed * w;
      ea += e.ea * w;
      ed_worst = std::max(ed_worst, e.ed);
      if (e.ea > ea_worst) ea_worst = e.ea, worst_center = c;
    }
  } log_flux, plain_flux, two_ring, auto_acc, log_trunc, full_log, full_plain, dem_acc;
  // Every estimator with and without the lattice correction (pipelines/include/locus/pipelines/geodesic/logmap.hpp).
  struct Variant {
    std::string name;
    LogMapEstimator est;
    Acc acc;
    int64_t flipped = 0;
    Json per_center = Json::array();
    double cpu_s = 0;  // mean thread CPU time of the localized query
  };
  std::vector<Variant> variants;
  for (auto [an, a] : {std::pair{"log", LogMapAngle::LogHeat}, std::pair{"two_ring", LogMapAngle::LogHeatTwoRing},
                       std::pair{"auto", LogMapAngle::Auto}})
    for (auto [ln, l] : {std::pair{"none", LatticeCorrection::None}, std::pair{"star", LatticeCorrection::Star},
                         std::pair{"ring", LatticeCorrection::Ring},
                         std::pair{"path", LatticeCorrection::Path}})
      for (bool rc : {false, true})
        variants.push_back({std::string(an) + "_" + ln + (rc ? "_recenter" : ""), {a, l, rc}, {}, 0, Json::array(), 0.0});
  int64_t flipped_heat = 0, flipped_two_ring = 0, flipped_auto = 0, auto_two_ring = 0, flipped_full = 0, flipped_dem = 0, fallbacks = 0, patch_total = 0;
  double local_vs_full_d = 0;
  LogMapWorkspace lws;
  DemWorkspace dws;
  std::vector<int32_t> scratch, dem_patch(n), dem_pos(n, -1);
  std::vector<double> du(n), dv(n);
  const double w = 1.0 / centers.size();
  for (int32_t c : centers) {
    ctx.check_cancel();
    std::vector<int32_t> patch{c};
    for (int32_t j = 0; j < n; ++j)
      if (j != c && s.exact_distance(c, j) <= ao.radius) patch.push_back(j);
    if (ao.patch_kind == "graph")  // the CLI's patch: a Dijkstra disk of as many vertices
      grow_patch_vertices(grower, c, geodesic_disk(static_cast<int32_t>(patch.size())), pws, patch);
    patch_total += static_cast<int64_t>(patch.size());
    Maps m;
    m.resize(patch.size());
    for (Variant& v : variants) {
      if (ao.quick) break;
      const double c0 = thread_cpu_seconds();
      heat.query(c, patch, m.out(), lws, v.est);
      v.cpu_s += (thread_cpu_seconds() - c0) * w;
      const Errors e = errors_of(s, c, patch, m.d, m.a);
      v.acc.add(e, w, c);
      v.per_center.push_back(e.ea);
      v.flipped += count_flipped_triangles(heat.geodesic().gradients(), patch, m.u, m.v, scratch);
      if (!ao.dump.empty() && v.name == ao.dump_variant) {
        std::FILE* fp = std::fopen(ao.dump.c_str(), c == centers.front() ? "w" : "a");
        if (!fp) fail(ErrorCode::BadUsage, "cannot write " + ao.dump);
        for (size_t p = 0; p < patch.size(); ++p)
          std::fprintf(fp, "%d,%d,%.9g,%.9g,%.9g,%.9g\n", c, patch[p], s.exact_distance(c, patch[p]),
                       exact_angle(s, c, patch[p]), m.d[p], m.a[p]);
        std::fclose(fp);
      }
    }
    LogMapStats st = heat.query(c, patch, m.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
    fallbacks += st.angle_fallbacks;
    log_flux.add(errors_of(s, c, patch, m.d, m.a), w, c);
    flipped_heat += count_flipped_triangles(heat.geodesic().gradients(), patch, m.u, m.v, scratch);
    heat.query(c, patch, m.out(), lws, LogMapAngle::HeatAverage);
    plain_flux.add(errors_of(s, c, patch, m.d, m.a), w, c);
    st = heat.query(c, patch, m.out(), lws, LogMapAngle::Auto);
    const Errors ea = errors_of(s, c, patch, m.d, m.a, nullptr, &bands_local);
    auto_acc.add(ea, w, c);
    {
      Bands own(ao.bands);
      errors_of(s, c, patch, m.d, m.a, nullptr, &own);
      per_center.push_back(Json{{"center", c}, {"valence", valence[c]}, {"patch_size", patch.size()},
                                {"two_ring", st.two_ring}, {"E_d", ea.ed}, {"E_a", ea.ea},
                                {"E_d_outer_band", own.mean_ed(ao.bands - 1, ao.bands)},
                                {"E_d_inner_half", own.mean_ed(0, ao.bands / 2)}});
    }
    auto_two_ring += st.two_ring;
    flipped_auto += count_flipped_triangles(heat.geodesic().gradients(), patch, m.u, m.v, scratch);
    heat.query(c, patch, m.out(), lws, LogMapAngle::LogHeatTwoRing);
    two_ring.add(errors_of(s, c, patch, m.d, m.a), w, c);
    flipped_two_ring += count_flipped_triangles(heat.geodesic().gradients(), patch, m.u, m.v, scratch);
    // Truncated Poisson right-hand side (distance only; the angle does not depend on it).
    HeatGeodesicWorkspace gws;
    std::vector<double> dt(patch.size());
    heat.geodesic().query(c, patch, dt, gws, HeatGeodesicOptions::PoissonRhs::Truncated);
    log_trunc.add(errors_of(s, c, patch, dt, m.a), w);
    if (!ao.no_full) {
      Maps f;
      f.resize(patch.size());
      heat.query_full(c, patch, f.out(), lws, LogMapAngle::Auto);
      errors_of(s, c, patch, f.d, f.a, nullptr, &bands_full);
      heat.query_full(c, patch, f.out(), lws, LogMapAngle::HeatAverage);
      full_plain.add(errors_of(s, c, patch, f.d, f.a), w, c);
      heat.query_full(c, patch, f.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
      full_log.add(errors_of(s, c, patch, f.d, f.a), w, c);
      flipped_full += count_flipped_triangles(heat.geodesic().gradients(), patch, f.u, f.v, scratch);
      Maps l2;
      l2.resize(patch.size());
      heat.query(c, patch, l2.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
      double md = 0;
      for (size_t p = 0; p < patch.size(); ++p) md = std::max(md, std::abs(l2.d[p] - f.d[p]));
      local_vs_full_d = std::max(local_vs_full_d, md);
    }
    // DEM over a graph-metric disk comfortably containing the exact one.
    const int32_t kd = dem.query(c, n, 1.5 * ao.radius, dem_patch, du, dv, dws);
    for (int32_t p = 0; p < kd; ++p) dem_pos[dem_patch[p]] = p;
    std::vector<double> dd(patch.size()), da(patch.size());
    std::vector<uint8_t> mapped(patch.size(), 0);
    for (size_t p = 0; p < patch.size(); ++p) {
      const int32_t q = dem_pos[patch[p]];
      if (q < 0) continue;
      mapped[p] = 1;
      dd[p] = std::hypot(du[q], dv[q]);
      da[p] = std::atan2(dv[q], du[q]);
    }
    dem_acc.add(errors_of(s, c, patch, dd, da, &mapped), w, c);
    flipped_dem += count_flipped_triangles(heat.geodesic().gradients(), std::span<const int32_t>(dem_patch.data(), kd),
                                           std::span<const double>(du.data(), kd),
                                           std::span<const double>(dv.data(), kd), scratch);
    for (int32_t p = 0; p < kd; ++p) dem_pos[dem_patch[p]] = -1;
  }
  auto pair = [](const Acc& a) {
    return Json{{"E_d", a.ed}, {"E_a", a.ea}, {"E_d_worst", a.ed_worst}, {"E_a_worst", a.ea_worst},
                {"worst_center", a.worst_center}};
  };
  Json j{{"command", "logmap-accuracy"}, {"surface", opt.mesh_path}};
  j["n"] = n;
  j["h"] = heat.geodesic().mean_edge_length();
  j["t_factor"] = lo.geodesic.t_factor;
  j["mass_blend"] = ao.mass_blend;
  j["distance_gradient"] = ao.plain_gradient ? "heat" : "log_heat";
  j["radius"] = ao.radius;
  j["centers"] = centers;
  j["mean_patch_size"] = static_cast<double>(patch_total) / centers.size();
  j["generate_s"] = generate_s;
  j["precompute_s"] = precompute_s;
  j["heat_local_logheat"] = pair(log_flux);
  j["heat_local_heataverage"] = pair(plain_flux);
  j["heat_local_auto"] = pair(auto_acc);
  j["auto_two_ring_centers"] = auto_two_ring;
  j["flipped_triangles_heat_auto"] = flipped_auto;
  j["heat_local_logheat_tworing"] = pair(two_ring);
  j["flipped_triangles_heat_tworing"] = flipped_two_ring;
  j["heat_local_truncated_rhs_distance"] = log_trunc.ed;
  if (!ao.no_full) {
    j["heat_full_logheat"] = pair(full_log);
    j["heat_full_heataverage"] = pair(full_plain);
    j["local_vs_full_distance_max"] = local_vs_full_d;
    j["flipped_triangles_heat_full"] = flipped_full;
  }
  j["dem"] = pair(dem_acc);
  j["lattice_correction"] = ao.lattice;
  Json var = Json::object();
  for (const Variant& v : variants) {
    Json e = pair(v.acc);
    e["flipped_triangles"] = v.flipped;
    e["E_a_per_center"] = v.per_center;
    e["query_cpu_s"] = v.cpu_s;
    var[v.name] = e;
  }
  j["variants"] = var;
  j["center_set"] = ao.center_set;
  j["patch"] = ao.patch_kind;
  j["per_center"] = per_center;  // the default map (heat_local_auto)
  j["radius_bands_local"] = bands_local.json();
  if (!ao.no_full) j["radius_bands_full"] = bands_full.json();
  j["flipped_triangles_heat"] = flipped_heat;
  j["flipped_triangles_dem"] = flipped_dem;
  j["angle_fallbacks"] = fallbacks;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

// ----------------------------------------------------- geodesic accuracy ----

struct GeodesicAccuracyOptions {
  int centers = 1;
  std::string center_ids = "0";
  double t_factor = 0;  // 0: the library's default, as in AccuracyOptions
  bool plain_gradient = false;
  double near = 0.5;  // the near-field radius of E_near
  double poisson_rel = HeatGeodesicOptions{}.poisson_rel;
};

// Whole-mesh heat geodesic distance (HeatGeodesic::query_full, the `locus
// geodesic` default) against the exact distance: mean and max over all
// vertices, inside --near, and by exact distance in bands of 0.25; the heat
// values' underflow (zero or subnormal) counted.
int run_geodesic_accuracy(const cli::CommonOptions& opt, const GeodesicAccuracyOptions& go, const RunContext& ctx) {
  const Surface s = make_surface(opt.mesh_path);
  AccuracyOptions ao;
  ao.centers = go.centers;
  ao.center_ids = go.center_ids;
  const std::vector<int32_t> centers = accuracy_centers(s, ao, opt.seed);
  const int32_t n = s.mesh.num_vertices();
  HeatGeodesicOptions ho;
  if (go.t_factor > 0) ho.t_factor = go.t_factor;
  ho.log_heat_gradient = !go.plain_gradient;
  ho.poisson_rel = go.poisson_rel;
  Stopwatch sw;
  // Polygon meshes (cube-sphere:N) through the polygon operators, whole mesh only.
  const bool polygons = !s.mesh.is_triangle_mesh();
  std::optional<HeatGeodesic> tri;
  std::optional<PolygonHeatGeodesic> poly;
  if (polygons) {
    PolygonHeatGeodesicOptions po;
    if (go.t_factor > 0) po.t_factor = go.t_factor;
    po.poisson_rel = go.poisson_rel;
    poly.emplace(s.mesh, po, ctx);
  } else {
    tri.emplace(s.mesh, ho, ctx);
  }
  const double h = polygons ? poly->mean_edge_length() : tri->mean_edge_length();
  const double t = polygons ? poly->time() : tri->time();
  const double precompute_s = sw.seconds();
  HeatGeodesicWorkspace ws;
  std::vector<double> d(static_cast<size_t>(n));
  const int nb = 13;  // bands of 0.25 up to pi
  std::vector<double> band_sum(nb, 0.0);
  std::vector<int64_t> band_cnt(nb, 0);
  double mean = 0, maxe = 0, near = 0, query_s = 0;
  int64_t near_cnt = 0, underflow = 0;
  for (int32_t c : centers) {
    ctx.check_cancel();
    sw.restart();
    if (polygons) {
      poly->query_full(c, d);
    } else {
      tri->query_full(c, d, ws);
      underflow += ws.underflow;
    }
    query_s += sw.seconds() / centers.size();
    double sum = 0;
    for (int32_t v = 0; v < n; ++v) {
      const double r = s.exact_distance(c, v), e = std::abs(d[v] - r);
      sum += e;
      maxe = std::max(maxe, e);
      if (r <= go.near) near += e, ++near_cnt;
      const int b = std::min(nb - 1, static_cast<int>(r / 0.25));
      band_sum[b] += e;
      ++band_cnt[b];
    }
    mean += sum / n / centers.size();
  }
  Json bands = Json::array();
  for (int b = 0; b < nb; ++b)
    if (band_cnt[b] > 0)
      bands.push_back(Json{{"from", 0.25 * b}, {"to", 0.25 * (b + 1)}, {"mean_error", band_sum[b] / band_cnt[b]}});
  Json j{{"command", "geodesic-accuracy"}, {"surface", opt.mesh_path}};
  j["n"] = n;
  j["h"] = h;
  j["t"] = t;
  j["t_factor"] = t / (h * h);
  j["polygons"] = polygons;
  j["centers"] = centers;
  j["mean_error"] = mean;
  j["max_error"] = maxe;
  j["near_radius"] = go.near;
  j["mean_error_near"] = near_cnt > 0 ? near / near_cnt : 0.0;
  j["underflow_vertices"] = underflow;
  j["bands"] = bands;
  j["precompute_s"] = precompute_s;
  j["query_s"] = query_s;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
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

  auto ao = std::make_shared<AccuracyOptions>();
  CLI::App* acc = table.add(
      "logmap-accuracy",
      "E_d / E_a against analytic maps; mesh-file is a surface spec: icosphere:L, random-sphere:N or bump:RINGS",
      [ao](const cli::CommonOptions& o, const RunContext& ctx) { return run_accuracy(o, *ao, ctx); });
  acc->add_option("--centers", ao->centers, "Random centers (spheres; the bump uses its top), default 3");
  acc->add_option("--radius", ao->radius, "Geodesic radius of the patch, default 0.5");
  acc->add_option("--t-factor", ao->t_factor, "t = c h^2 (default: the library's, 4 for triangles, 8 for polygon meshes)");
  acc->add_flag("--no-full", ao->no_full, "Skip the full-solve variant");
  acc->add_flag("--plain-gradient", ao->plain_gradient, "Distance from grad h (Crane et al.) instead of grad log h");
  acc->add_option("--center-ids", ao->center_ids, "Comma-separated center vertices instead of random ones");
  acc->add_option("--lattice", ao->lattice, "Lattice correction of the unnamed rows: none, star, ring, path (default: the library's)");
  acc->add_option("--recenter,--recentre", ao->recenter, "Recenter the gradients in the unnamed rows: on, off (default: the library's)");
  acc->add_option("--mass-blend", ao->mass_blend, "Heat operator mass: (1 - b) lumped + b consistent (default 0)");
  acc->add_option("--dump", ao->dump, "CSV of per-vertex exact and computed (distance, angle) of --dump-variant");
  acc->add_option("--dump-variant", ao->dump_variant, "Variant written by --dump (default log_none; see 'variants')");
  acc->add_option("--center-set", ao->center_set,
                  "random (default) or irregular: --centers vertices of valence != 6 (icospheres: the 12 corners)");
  acc->add_option("--patch", ao->patch_kind,
                  "exact (default): the vertices within --radius; graph: the Dijkstra disk of as many vertices (the CLI's)");
  acc->add_flag("--quick", ao->quick, "Only the default map, full solves and DEM (no estimator variants)");
  acc->add_option("--bands", ao->bands, "Radius bands of the default map's errors (default 10)");
  auto go = std::make_shared<GeodesicAccuracyOptions>();
  CLI::App* geo = table.add(
      "geodesic-accuracy",
      "Whole-mesh heat geodesic distance against the exact one; mesh-file is a surface spec (see logmap-accuracy)",
      [go](const cli::CommonOptions& o, const RunContext& ctx) { return run_geodesic_accuracy(o, *go, ctx); });
  geo->add_option("--center-ids", go->center_ids, "Comma-separated source vertices (default 0)");
  geo->add_option("--t-factor", go->t_factor, "t = c h^2 (default: the library's, 4 for triangles, 8 for polygon meshes)");
  geo->add_flag("--plain-gradient", go->plain_gradient, "Direction from grad h (Crane et al.) instead of grad log h");
  geo->add_option("--poisson-rel", go->poisson_rel, "Regularization of the Poisson operator (HeatGeodesicOptions::poisson_rel)");
  geo->add_option("--near", go->near, "Radius of the near-field error (default 0.5)");
  acc->add_option("--save-surface", ao->save_surface, "Write the generated surface to this file (.off, .ply, .obj)");
}

}  // namespace locus::bench
