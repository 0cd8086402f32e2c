// `locus-bench voronoi-convergence random-sphere`: the bisector convergence study of
// thesis §3.4 (Fig. 3.1, eq. 3.22). On random-point hulls of the unit sphere of
// increasing size, generators at (1,0,0), (-1,0,0), (0,1,0) (as surface points on
// the faces the axis rays cross); the heat Voronoi diagram (pipelines/voronoi/heat_voronoi)
// and the RMS over its edge points of the distance to the exact bisector plane
// (all bisectors of the sphere lie in planes through the origin). Reports h, RMS
// per size and t, and the least-squares slope of log RMS against log h (quadratic
// convergence: 2). The test suite runs two sizes; this runs as many as given.
//
// `locus-bench cvt-speed MESH --sites N --iters K`: Lloyd CVT (thesis §3.7.1) with
// localized and with full solves in the same process, on one prepared factor of
// M - 4h^2 L (kLloydTFactor, as `locus cvt`) and the same random initial sites (--seed); per-iteration wall time
// and process CPU time (between consecutive iteration reports; the first
// iteration, whose neighborhoods are Dijkstra balls, is left out), medians and
// the full/local ratios, and the load average before and after. --rounds R
// alternates the solvers R times and takes the medians over all rounds. JSON also
// has the thread CPU time of the solves alone (ratio_solve_cpu) and, from an extra
// untimed local run, the factor entries one batch reads against a full solve
// (reads: selective_solve_reads / 2 factor_entries, and the bounds 1 / fraction).
#include <time.h>

#include <cmath>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/solve/solve_selective.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
#include "tools/bench/bench_commands.hpp"

namespace locus::bench {
namespace {

using cli::Json;

struct ConvergenceOptions {
  std::string sizes = "1000,4000,16000,64000";
  std::string times = "1,0.0078125";
};

std::vector<double> parse_list(const std::string& text, const char* what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size() || !(v > 0) || !std::isfinite(v))
      fail(ErrorCode::BadUsage, std::string(what) + " expects comma-separated positive numbers, got '" + text + "'");
    out.push_back(v);
  }
  if (out.empty()) fail(ErrorCode::BadUsage, std::string(what) + " is empty");
  return out;
}

// The face the ray from the origin along d crosses (convex mesh around the origin), by Cramer's rule.
SurfacePoint ray_point(const Mesh& m, const double d[3]) {
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    double P[3][3];
    for (int k = 0; k < 3; ++k) {
      P[0][k] = m.x[v[k]];
      P[1][k] = m.y[v[k]];
      P[2][k] = m.z[v[k]];
    }
    auto det = [](const double A[3][3]) {
      return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
             A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    };
    const double D = det(P);
    if (D == 0) continue;
    double w[3];
    for (int k = 0; k < 3; ++k) {
      double Q[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) Q[r][c] = c == k ? d[r] : P[r][c];
      w[k] = det(Q) / D;
    }
    const double s = w[0] + w[1] + w[2];
    if (w[0] >= 0 && w[1] >= 0 && w[2] >= 0 && s > 0) return SurfacePoint{f, -1, {w[0] / s, w[1] / s, w[2] / s}};
  }
  fail(ErrorCode::Numerical, "no face crosses the generator's ray");
}

int run_convergence(const cli::CommonOptions& opt, const ConvergenceOptions& o, const RunContext& ctx) {
  if (opt.mesh_path != "random-sphere")
    fail(ErrorCode::BadUsage, "voronoi-convergence generates its meshes: give 'random-sphere' as the mesh");
  const std::vector<double> sizes = parse_list(o.sizes, "--sizes"), times = parse_list(o.times, "--t");
  const double gen[3][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
  Json j{{"command", "voronoi-convergence"}, {"seed", opt.seed}};
  Json rows = Json::array();
  std::vector<double> logh;
  std::vector<std::vector<double>> loge(times.size());
  for (double sz : sizes) {
    ctx.check_cancel();
    const Mesh m = make_random_sphere(static_cast<int32_t>(sz), opt.seed);
    std::vector<SurfacePoint> sites;
    for (const auto& g : gen) sites.push_back(ray_point(m, g));
    const double h = mean_edge_length(m);
    logh.push_back(std::log(h));
    Json row{{"n", m.num_vertices()}, {"h", h}};
    for (size_t ti = 0; ti < times.size(); ++ti) {
      const HeatDiffusion H = prepare_heat_diffusion(m, 1.0, times[ti], ctx);
      const HeatVoronoi V = heat_voronoi(H, m, sites, {}, {}, ctx);
      const VoronoiDiagram D = extract_voronoi_diagram(H, m, sites, V, ctx);
      double sum = 0;
      int64_t cnt = 0;
      for (size_t p = 0; p < D.points.size() / 3; ++p) {
        const int32_t a = D.point_edge_sites[2 * p], b = D.point_edge_sites[2 * p + 1];
        if (a < 0) continue;
        double nrm[3], len = 0;
        for (int c = 0; c < 3; ++c) {
          nrm[c] = gen[a][c] - gen[b][c];
          len += nrm[c] * nrm[c];
        }
        const double e = (D.points[3 * p] * nrm[0] + D.points[3 * p + 1] * nrm[1] + D.points[3 * p + 2] * nrm[2]) /
                         std::sqrt(len);  // eq. 3.22
        sum += e * e;
        ++cnt;
      }
      const double rms = cnt ? std::sqrt(sum / cnt) : 0.0;
      loge[ti].push_back(std::log(rms));
      row["rms_t" + cli::format_number(times[ti])] = rms;
      row["points_t" + cli::format_number(times[ti])] = cnt;
    }
    rows.push_back(row);
  }
  j["rows"] = rows;
  Json slopes = Json::object();
  for (size_t ti = 0; ti < times.size(); ++ti) {  // least-squares slope of log rms on log h
    const size_t k = logh.size();
    double mx = 0, my = 0;
    for (size_t i = 0; i < k; ++i) {
      mx += logh[i] / k;
      my += loge[ti][i] / k;
    }
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < k; ++i) {
      sxy += (logh[i] - mx) * (loge[ti][i] - my);
      sxx += (logh[i] - mx) * (logh[i] - mx);
    }
    slopes["t" + cli::format_number(times[ti])] = sxx > 0 ? sxy / sxx : 0.0;
  }
  j["slopes"] = slopes;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

struct CvtSpeedOptions {
  int32_t sites = 1000;
  int32_t iterations = 6;
  std::string solvers = "local,full";
  int32_t rounds = 1;
};

double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string load_average() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

int run_cvt_speed(const cli::CommonOptions& opt, const CvtSpeedOptions& o, const RunContext& ctx) {
  if (o.iterations < 2) fail(ErrorCode::BadUsage, "cvt-speed: --iters must be at least 2 (the first iteration is not timed)");
  if (o.solvers != "local,full" && o.solvers != "local" && o.solvers != "full")
    fail(ErrorCode::BadUsage, "cvt-speed: --solvers is local, full or local,full");
  const cli::Input in = cli::load_input(opt, ctx);
  const Mesh& m = in.mesh;
  if (o.sites < 1 || o.sites > m.num_vertices()) fail(ErrorCode::BadUsage, "cvt-speed: --sites out of range");
  Json j{{"command", "cvt-speed"}, {"n", m.num_vertices()}, {"sites", o.sites}, {"iterations", o.iterations},
         {"seed", opt.seed}, {"threads", ctx.threads}, {"load_before", load_average()}};
  const double f0 = process_cpu_s();
  const HeatDiffusion H = prepare_heat_diffusion(m, kLloydTFactor, 0.0, ctx);  // as `locus cvt`
  j["factor_cpu_s"] = process_cpu_s() - f0;
  const std::vector<SurfacePoint> init = random_surface_points(m, o.sites, opt.seed);
  std::vector<std::string> solvers;
  if (o.solvers != "full") solvers.push_back("local");
  if (o.solvers != "local") solvers.push_back("full");
  if (o.rounds < 1) fail(ErrorCode::BadUsage, "cvt-speed: --rounds must be at least 1");
  double wall[2] = {0, 0}, cpu[2] = {0, 0};
  double solve_cpu[2] = {0, 0};  // thread CPU in the solves alone, all rounds (first and final labels included)
  // Per solver, the iteration times of every round (rounds alternate local and full,
  // so a change in the machine's load hits both alike).
  std::vector<double> wall_all[2], cpu_all[2];
  for (int32_t round = 0; round < o.rounds; ++round) {
    for (size_t k = 0; k < solvers.size(); ++k) {
      LloydOptions lo;
      lo.iterations = o.iterations;
      lo.prepared = &H;
      lo.solver = solvers[k] == "full" ? LloydOptions::Solver::Full : LloydOptions::Solver::Local;
      std::vector<double> marks;  // process CPU time at the end of each iteration (reported on this thread)
      RunContext run = ctx;
      run.progress = [&marks](double, std::string_view phase) {
        if (phase == "lloyd") marks.push_back(process_cpu_s());
      };
      const LloydResult r = cvt_lloyd(m, init, lo, run);
      std::vector<double> cpu_it, wall_it(r.iter_s.begin() + 1, r.iter_s.end());
      for (size_t i = 1; i < marks.size(); ++i) cpu_it.push_back(marks[i] - marks[i - 1]);
      const CvtQuality q = cvt_quality(m, r.label, r.sites);
      const int slot = solvers[k] == "full" ? 1 : 0;
      wall_all[slot].insert(wall_all[slot].end(), wall_it.begin(), wall_it.end());
      cpu_all[slot].insert(cpu_all[slot].end(), cpu_it.begin(), cpu_it.end());
      solve_cpu[slot] += r.label_solve_cpu_s + r.centroid_solve_cpu_s;
      wall[slot] = cli::median(wall_all[slot]);
      cpu[slot] = cli::median(cpu_all[slot]);
      j[solvers[k]] = {{"iter_s", wall[slot]},
                       {"iter_cpu_s", cpu[slot]},
                       {"iter_s_all", wall_all[slot]},
                       {"iter_cpu_s_all", cpu_all[slot]},
                       {"phase_s", {{"labels", r.labels_s}, {"partition", r.partition_s},
                                    {"neighborhoods", r.neighborhood_s}, {"centroids", r.centroids_s}}},
                       {"mean_kept_fraction", r.mean_kept_fraction},
                       {"solve_cpu_s", {{"labels", r.label_solve_cpu_s}, {"centroids", r.centroid_solve_cpu_s}}},
                       {"mean_angle_deg", q.mean_angle_deg},
                       {"min_angle_deg", q.min_angle_deg}};
    }
  }
  if (o.solvers != "full") {
    // Untimed extra local run: the factor entries one batch's solves read against a
    // full forward + backward solve (the counting pass would distort the timings).
    LloydOptions lo;
    lo.iterations = o.iterations;
    lo.prepared = &H;
    lo.count_reads = true;
    const LloydResult r = cvt_lloyd(m, init, lo, ctx);
    const double mixed = 0.5 * (r.centroid_read_fraction + r.label_read_fraction);
    j["reads"] = {{"factor_entries", factor_entries(*H.factor.symbolic)},
                  {"centroid_read_fraction", r.centroid_read_fraction},
                  {"label_read_fraction", r.label_read_fraction},
                  {"bound_centroid", r.centroid_read_fraction > 0 ? 1.0 / r.centroid_read_fraction : 0.0},
                  {"bound_label", r.label_read_fraction > 0 ? 1.0 / r.label_read_fraction : 0.0},
                  {"bound_iteration", mixed > 0 ? 1.0 / mixed : 0.0}};
  }
  if (solvers.size() == 2) {
    j["ratio_wall"] = wall[0] > 0 ? wall[1] / wall[0] : 0.0;
    j["ratio_cpu"] = cpu[0] > 0 ? cpu[1] / cpu[0] : 0.0;
    // The same ratio for the solves alone: what the localized iteration would gain
    // if everything around its solves cost nothing.
    j["ratio_solve_cpu"] = solve_cpu[0] > 0 ? solve_cpu[1] / solve_cpu[0] : 0.0;
  }
  j["load_after"] = load_average();
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

// `locus-bench cvt-bias MESH --sites N --warmup K --variants ...`: how far heat
// centroids sit from the area centroids of their cells, for several centroid
// variants on the SAME cells: K Lloyd iterations with the defaults give the sites,
// then every variant runs one iteration from them (same labels, same cells), and
// LloydResult::centroid_bias of that iteration is reported (RMS, median, 90th
// percentile over the cells, units of h) with the iteration's time.
// A variant is "tc:rings[:sigma]" (t_centroid_factor, fit_rings, fit_sigma; tc 0 =
// the cells' t; sigma defaults to LloydOptions').
// The warm-up uses the defaults of LloydOptions.
struct CvtBiasOptions {
  int32_t sites = 1000;
  int32_t warmup = 60;
  std::string variants = "0:2";
  std::string solver = "local";
};

int run_cvt_bias(const cli::CommonOptions& opt, const CvtBiasOptions& o, const RunContext& ctx) {
  // MESH may also be random-sphere:N (convex hull of N random unit vectors: irregular
  // triangles, smooth constant curvature).
  Mesh sphere;
  const bool gen = opt.mesh_path.rfind("random-sphere:", 0) == 0;
  if (gen) sphere = make_random_sphere(static_cast<int32_t>(std::stol(opt.mesh_path.substr(14))), opt.seed);
  const cli::Input in = gen ? cli::Input{} : cli::load_input(opt, ctx);
  const Mesh& m = gen ? sphere : in.mesh;
  if (o.sites < 1 || o.sites > m.num_vertices()) fail(ErrorCode::BadUsage, "cvt-bias: --sites out of range");
  if (o.warmup < 0) fail(ErrorCode::BadUsage, "cvt-bias: --warmup must be >= 0");
  if (o.solver != "local" && o.solver != "full") fail(ErrorCode::BadUsage, "cvt-bias: --solver is local or full");
  const HeatDiffusion H = prepare_heat_diffusion(m, kLloydTFactor, 0.0, ctx);  // as `locus cvt`
  LloydOptions base;
  base.iterations = o.warmup;
  base.prepared = &H;
  base.solver = o.solver == "full" ? LloydOptions::Solver::Full : LloydOptions::Solver::Local;
  const std::vector<SurfacePoint> sites =
      cvt_lloyd(m, random_surface_points(m, o.sites, opt.seed), base, ctx).sites;
  Json j{{"command", "cvt-bias"}, {"n", m.num_vertices()}, {"sites", o.sites}, {"warmup", o.warmup},
         {"seed", opt.seed}, {"solver", o.solver}, {"load_before", load_average()}};
  Json rows = Json::array();
  std::stringstream ss(o.variants);
  std::string spec;
  while (std::getline(ss, spec, ',')) {
    double tc = 0, sigma = LloydOptions{}.fit_sigma;
    int rings = 2;
    char c1 = 0, c2 = ':';
    std::stringstream vs(spec);
    const bool ok = static_cast<bool>(vs >> tc >> c1 >> rings);
    if (ok && !vs.eof()) vs >> c2 >> sigma;
    if (!ok || vs.fail() || !vs.eof() || c1 != ':' || c2 != ':' || !(sigma >= 0))
      fail(ErrorCode::BadUsage, "cvt-bias: a variant is tc:rings[:sigma], got '" + spec + "'");
    LloydOptions lo = base;
    lo.iterations = 1;
    lo.t_centroid_factor = tc;
    lo.fit_rings = rings;
    lo.fit_sigma = sigma;
    const LloydResult r = cvt_lloyd(m, sites, lo, ctx);
    rows.push_back({{"variant", spec},
                    {"bias_rms_h", r.centroid_bias.at(0)},
                    {"bias_median_h", r.centroid_bias_median.at(0)},
                    {"centroids_s", r.centroids_s}});
  }
  j["variants"] = rows;
  j["load_after"] = load_average();
  cli::emit(opt, j, [&](std::ostream& os) {
    for (const auto& row : j["variants"])
      os << row["variant"].get<std::string>() << "  rms " << row["bias_rms_h"].get<double>() << "  median "
         << row["bias_median_h"].get<double>() << "  centroids_s " << row["centroids_s"].get<double>() << "\n";
  });
  return 0;
}

}  // namespace

void register_voronoi_bench(cli::CommandTable& table) {
  auto o = std::make_shared<ConvergenceOptions>();
  CLI::App* app = table.add(
      "voronoi-convergence", "Heat Voronoi bisector RMS error vs mean edge length on random unit spheres (thesis Fig. 3.1)",
      [o](const cli::CommonOptions& opt, const RunContext& ctx) { return run_convergence(opt, *o, ctx); });
  app->add_option("--sizes", o->sizes, "Vertex counts of the random spheres (default 1000,4000,16000,64000)");
  app->add_option("--t", o->times, "Absolute diffusion times (default 1,0.0078125 = 2^0, 2^-7)");
  // Registered here so that the bench's registration list does not change.
  auto c = std::make_shared<CvtSpeedOptions>();
  CLI::App* capp = table.add(
      "cvt-speed", "Lloyd CVT per-iteration time, localized vs full solves in one process (thesis 3.7.1)",
      [c](const cli::CommonOptions& opt, const RunContext& ctx) { return run_cvt_speed(opt, *c, ctx); });
  capp->add_option("--sites", c->sites, "Number of sites (default 1000)");
  capp->add_option("--iters", c->iterations, "Lloyd iterations per solver (default 6; the first is not timed)");
  capp->add_option("--solvers", c->solvers, "local,full (default), local or full");
  capp->add_option("--rounds", c->rounds,
                   "Alternating rounds of the solvers (default 1); medians over the timed iterations of all rounds");
  auto b = std::make_shared<CvtBiasOptions>();
  CLI::App* bapp = table.add(
      "cvt-bias", "Heat centroid vs area centroid of the same cells, per centroid variant (thesis 3.5)",
      [b](const cli::CommonOptions& opt, const RunContext& ctx) { return run_cvt_bias(opt, *b, ctx); });
  bapp->add_option("--sites", b->sites, "Number of sites (default 1000)");
  bapp->add_option("--warmup", b->warmup, "Lloyd iterations with the defaults before measuring (default 60)");
  bapp->add_option("--variants", b->variants, "Comma-separated tc:rings[:sigma] (default 0:2)");
  bapp->add_option("--solver", b->solver, "local (default) or full");
}

}  // namespace locus::bench
