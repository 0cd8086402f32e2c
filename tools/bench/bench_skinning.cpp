// `locus-bench skinning MESH --handles K`: skinning weights (thesis §3.7.2,
// pipelines/include/locus/pipelines/voronoi/skinning_weights.hpp) by the sampled
// method (one run per --samples value) and, where the mesh is small enough, the
// exact per-vertex method, on one prepared heat operator; and the coarse road
// (skinning_coarse.hpp; with its own coarse operator, timed with it;
// --coarse-only runs just that one). Per method: wall time
// (median of --repeats; exact runs once), the max and mean |w - w_exact| over
// all weights, and the properties: min weight, max |sum - 1|, % exact zeros,
// the largest deviation of a handle vertex's row from its indicator, and the
// locality check: weights > 0 where the exact weight is 0 and no neighbor's
// exact weight is > 0 (outside a one-ring band of the natural neighbourhood).
// Handles: --handle-ids, else on armadillo (and its subdivisions, which keep the
// vertex ids) the head, hands, feet, tail and chest vertices of the skinning
// comparison with Blender, else farthest points (Dijkstra from vertex 0).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/skinning_coarse.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/cli/site_args.hpp"

namespace locus::bench {
namespace {

using cli::Json;

struct SkinningBenchOptions {
  int32_t handles = 4;
  std::string handle_ids;
  std::string samples = "1024";
  int32_t repeats = 3;
  int32_t exact_max_vertices = 30000;
  std::string exact_cache;  // file of the exact weights: read when it matches, else written
  bool coarse_only = false;
  double t_factor = 1.0;  // diffusion time t = t_factor * h^2 (skinweights' --t)
  int32_t worst = 0;      // list this many vertices of the largest |w - w_exact|
  std::string vertex_csv; // per-vertex features and errors (diagnostic)
  int32_t exact_up_to = SkinningOptions{}.exact_up_to;  // the small-mesh exact road's size (0: off)
};

// Head, left hand, right hand, right foot, left foot, tail, chest of armadillo.off.
constexpr int32_t kArmadilloHandles[] = {4530, 7448, 3233, 17208, 12411, 11820, 10158};

// k vertices by farthest-point sampling on edge-length Dijkstra, starting from
// the vertex farthest from vertex 0.
std::vector<int32_t> farthest_handles(const Mesh& m, int32_t k) {
  const int32_t n = m.num_vertices();
  const Adjacency adj = vertex_adjacency(m);
  std::vector<double> d(n, std::numeric_limits<double>::infinity());
  auto relax_from = [&](int32_t s) {
    std::vector<std::pair<double, int32_t>> heap{{0.0, s}};
    std::vector<double> ds(n, std::numeric_limits<double>::infinity());
    ds[s] = 0;
    auto cmp = [](const auto& a, const auto& b) { return a.first > b.first; };
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), cmp);
      const auto [dv, v] = heap.back();
      heap.pop_back();
      if (dv > ds[v]) continue;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
        const int32_t w = adj.neighbors[p];
        const double l = std::hypot(m.x[v] - m.x[w], m.y[v] - m.y[w], m.z[v] - m.z[w]);
        if (dv + l < ds[w]) {
          ds[w] = dv + l;
          heap.push_back({ds[w], w});
          std::push_heap(heap.begin(), heap.end(), cmp);
        }
      }
    }
    for (int32_t v = 0; v < n; ++v) d[v] = std::min(d[v], ds[v]);
  };
  auto farthest = [&] {
    int32_t best = 0;
    for (int32_t v = 0; v < n; ++v)
      if (std::isfinite(d[v]) && d[v] > d[best]) best = v;
    return best;
  };
  relax_from(0);
  std::vector<int32_t> h{farthest()};
  std::fill(d.begin(), d.end(), std::numeric_limits<double>::infinity());
  relax_from(h[0]);
  while (static_cast<int32_t>(h.size()) < k) {
    h.push_back(farthest());
    relax_from(h.back());
  }
  return h;
}

std::vector<int32_t> bench_handles(const cli::CommonOptions& opt, const SkinningBenchOptions& o, const Mesh& m) {
  if (!o.handle_ids.empty()) return cli::parse_vertex_list("--handle-ids", o.handle_ids);
  if (o.handles < 1) fail(ErrorCode::BadUsage, "skinning: --handles must be at least 1");
  const bool armadillo = opt.mesh_path.find("armadillo.off") != std::string::npos && m.num_vertices() >= 26002;
  if (armadillo && o.handles <= 7) return {kArmadilloHandles, kArmadilloHandles + o.handles};
  return farthest_handles(m, o.handles);
}

Json properties(const Mesh& m, const SkinningWeights& W, std::span<const int32_t> handles) {
  const int32_t n = m.num_vertices(), k = W.handles;
  double wmin = INFINITY, sum_err = 0, handle_err = 0;
  int64_t zeros = 0;
  for (int32_t v = 0; v < n; ++v) {
    double s = 0;
    for (int32_t j = 0; j < k; ++j) {
      const double w = W.weight[static_cast<size_t>(v) * k + j];
      wmin = std::min(wmin, w);
      zeros += w == 0.0;
      s += w;
    }
    sum_err = std::max(sum_err, std::abs(s - 1));
  }
  for (int32_t j = 0; j < k; ++j)
    for (int32_t i = 0; i < k; ++i)
      handle_err = std::max(handle_err, std::abs(W.weight[static_cast<size_t>(handles[j]) * k + i] - (i == j)));
  return {{"min_weight", wmin}, {"max_sum_error", sum_err},
          {"exact_zero_percent", 100.0 * static_cast<double>(zeros) / (static_cast<double>(n) * k)},
          {"max_handle_row_error", handle_err}};
}

// How far the exact weights jump between neighbours: the largest |w(u) - w(v)|
// over edges and the share of edges where some weight jumps by more than 0.05.
// A propagation from samples follows the weights only as far as they are smooth.
Json roughness(const Adjacency& adj, const SkinningWeights& E) {
  const int32_t n = static_cast<int32_t>(adj.offsets.size()) - 1, k = E.handles;
  double jmax = 0;
  int32_t at[2] = {-1, -1};
  int64_t edges = 0, rough = 0;
  for (int32_t v = 0; v < n; ++v)
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t u = adj.neighbors[p];
      if (u < v) continue;
      double j = 0;
      for (int32_t i = 0; i < k; ++i)
        j = std::max(j, std::abs(E.weight[static_cast<size_t>(u) * k + i] - E.weight[static_cast<size_t>(v) * k + i]));
      if (j > jmax) {
        jmax = j;
        at[0] = v;
        at[1] = u;
      }
      ++edges;
      rough += j > 0.05;
    }
  return {{"max_edge_jump", jmax}, {"max_edge_jump_at", {at[0], at[1]}},
          {"edges_jump_over_0_05_percent", edges ? 100.0 * rough / edges : 0.0}};
}

// Differences against the exact weights, and the locality check (header).
void compare(const Mesh& m, const Adjacency& adj, const SkinningWeights& W, const SkinningWeights& E, Json& j) {
  const int32_t n = m.num_vertices(), k = W.handles;
  double dmax = 0, dsum = 0;
  int32_t at = -1;
  int64_t outside = 0, zero_exact = 0;
  for (int32_t v = 0; v < n; ++v)
    for (int32_t i = 0; i < k; ++i) {
      const size_t a = static_cast<size_t>(v) * k + i;
      const double d = std::abs(W.weight[a] - E.weight[a]);
      if (d > dmax) {
        dmax = d;
        at = v;
      }
      dsum += d;
      if (E.weight[a] != 0.0) continue;
      bool band = false;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1] && !band; ++p)
        band = E.weight[static_cast<size_t>(adj.neighbors[p]) * k + i] > 0;
      if (band) continue;
      ++zero_exact;
      outside += W.weight[a] > 0;
    }
  j["max_diff"] = dmax;
  j["max_diff_vertex"] = at;
  j["mean_diff"] = dsum / (static_cast<double>(n) * k);
  j["nonzero_outside_band"] = outside;
  j["nonzero_outside_band_percent"] = zero_exact ? 100.0 * outside / zero_exact : 0.0;
}

// max_i |A(a, i) - B(b, i)|: the largest difference between row a of A and row b of B.
double row_diff(const SkinningWeights& A, int32_t a, const SkinningWeights& B, int32_t b) {
  const int32_t k = A.handles;
  double d = 0;
  for (int32_t i = 0; i < k; ++i)
    d = std::max(d, std::abs(A.weight[static_cast<size_t>(a) * k + i] - B.weight[static_cast<size_t>(b) * k + i]));
  return d;
}

// The `worst` vertices of the largest |w - w_exact|, each with what a rule could
// see there: the distance in rings to the nearest exact row (a row bitwise equal
// to the exact one), the exact neighbours' count, the spread of the exact rows
// over the one-ring, the longest incident edge over the mean edge, the valence.
Json worst_vertices(const Mesh& m, const Adjacency& adj, const SkinningWeights& W, const SkinningWeights& E, int32_t worst) {
  const int32_t n = m.num_vertices(), k = W.handles;
  std::vector<uint8_t> exact(n);
  std::vector<std::pair<double, int32_t>> err(n);
  for (int32_t v = 0; v < n; ++v) {
    exact[v] = std::equal(W.weight.begin() + static_cast<size_t>(v) * k, W.weight.begin() + static_cast<size_t>(v + 1) * k,
                          E.weight.begin() + static_cast<size_t>(v) * k);
    err[v] = {-row_diff(W, v, E, v), v};
  }
  const double h = mean_edge_length(m);
  std::sort(err.begin(), err.end());
  Json out = Json::array();
  int64_t nexact = 0;
  for (uint8_t e : exact) nexact += e;
  for (int32_t r = 0; r < std::min(worst, n); ++r) {
    const int32_t v = err[r].second;
    std::vector<int32_t> ring(n, -1), q{v};
    ring[v] = 0;
    int32_t near = -1;
    for (size_t i = 0; i < q.size() && near < 0; ++i) {
      if (exact[q[i]]) near = ring[q[i]];
      for (int64_t p = adj.offsets[q[i]]; p < adj.offsets[q[i] + 1]; ++p)
        if (ring[adj.neighbors[p]] < 0) {
          ring[adj.neighbors[p]] = ring[q[i]] + 1;
          q.push_back(adj.neighbors[p]);
        }
    }
    int32_t ex = 0;
    double lmax = 0, spread = 0, own = 0, residual = 0;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t u = adj.neighbors[p];
      ex += exact[u];
      lmax = std::max(lmax, std::hypot(m.x[u] - m.x[v], m.y[u] - m.y[v], m.z[u] - m.z[v]));
      own = std::max(own, row_diff(E, u, E, v));
      if (exact[u]) residual = std::max(residual, row_diff(W, u, W, v));
      for (int64_t p2 = adj.offsets[v]; p2 < adj.offsets[v + 1]; ++p2) spread = std::max(spread, row_diff(E, u, E, adj.neighbors[p2]));
    }
    out.push_back({{"v", v}, {"err", -err[r].first}, {"exact", static_cast<int>(exact[v])}, {"rings_to_exact", near},
                   {"exact_nbrs", ex}, {"valence", adj.offsets[v + 1] - adj.offsets[v]},
                   {"max_edge_over_h", lmax / h}, {"exact_jump_to_nbrs", own}, {"exact_nbr_spread", spread},
                   {"diff_to_exact_nbrs", residual}});
  }
  Json outside = Json::array();  // entries outside the one-ring band (compare)
  for (int32_t v = 0; v < n; ++v)
    for (int32_t i = 0; i < k; ++i) {
      const size_t a = static_cast<size_t>(v) * k + i;
      if (E.weight[a] != 0.0 || !(W.weight[a] > 0)) continue;
      bool band = false;
      for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1] && !band; ++p)
        band = E.weight[static_cast<size_t>(adj.neighbors[p]) * k + i] > 0;
      if (!band) outside.push_back({{"v", v}, {"handle", i}, {"w", W.weight[a]}});
    }
  return {{"exact_rows_bitwise", nexact}, {"vertices", out}, {"outside", outside}};
}

void write_vertex_csv(const std::string& path, const Mesh& m, const Adjacency& adj, const SkinningWeights& W,
                      const SkinningWeights& E) {
  const int32_t n = m.num_vertices(), k = W.handles;
  const double h = mean_edge_length(m);
  std::vector<double> amax(n, 0), amin(n, 180), area(n, 0);
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const int32_t c[3] = {m.f0[f], m.f1[f], m.f2[f]};
    for (int e = 0; e < 3; ++e) {
      const int32_t a = c[e], b = c[(e + 1) % 3], d = c[(e + 2) % 3];
      const double ux = m.x[b] - m.x[a], uy = m.y[b] - m.y[a], uz = m.z[b] - m.z[a];
      const double vx = m.x[d] - m.x[a], vy = m.y[d] - m.y[a], vz = m.z[d] - m.z[a];
      const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
      const double ang = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), ux * vx + uy * vy + uz * vz) * 180 / M_PI;
      amax[a] = std::max(amax[a], ang);
      amin[a] = std::min(amin[a], ang);
      area[a] += 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz) / 3;
    }
  }
  std::ofstream f(path);
  f << "v,err,exact,iso,jump,valence,lmax,lmin,amax,amin,area,area_ratio\n";
  for (int32_t v = 0; v < n; ++v) {
    const bool ex = std::equal(W.weight.begin() + static_cast<size_t>(v) * k, W.weight.begin() + static_cast<size_t>(v + 1) * k,
                               E.weight.begin() + static_cast<size_t>(v) * k);
    double iso = 1e9, jump = 0, lmax = 0, lmin = 1e9, na = 0;
    for (int64_t p = adj.offsets[v]; p < adj.offsets[v + 1]; ++p) {
      const int32_t u = adj.neighbors[p];
      const double d = row_diff(E, u, E, v);
      iso = std::min(iso, d);
      jump = std::max(jump, d);
      const double l = std::hypot(m.x[u] - m.x[v], m.y[u] - m.y[v], m.z[u] - m.z[v]) / h;
      lmax = std::max(lmax, l);
      lmin = std::min(lmin, l);
      na += area[u];
    }
    const int64_t deg = adj.offsets[v + 1] - adj.offsets[v];
    f << v << ',' << row_diff(W, v, E, v) << ',' << ex << ',' << iso << ',' << jump << ',' << deg << ',' << lmax << ','
      << lmin << ',' << amax[v] << ',' << amin[v] << ',' << area[v] / (h * h) << ',' << (deg ? area[v] * deg / na : 0)
      << '\n';
  }
}

// The exact weights cached in a raw file (n, k, handle ids, n * k doubles), so
// repeated benchmark runs of the fast methods skip the slow exact reference.
bool read_exact(const std::string& path, int32_t n, std::span<const int32_t> ids, SkinningWeights& E) {
  if (path.empty()) return false;
  std::ifstream f(path, std::ios::binary);
  int32_t hn = 0, hk = 0;
  if (!f.read(reinterpret_cast<char*>(&hn), 4) || !f.read(reinterpret_cast<char*>(&hk), 4)) return false;
  if (hn != n || hk != static_cast<int32_t>(ids.size())) return false;
  std::vector<int32_t> hid(hk);
  if (!f.read(reinterpret_cast<char*>(hid.data()), 4 * static_cast<std::streamsize>(hk))) return false;
  if (!std::equal(hid.begin(), hid.end(), ids.begin())) return false;
  E.handles = hk;
  E.method = "exact";
  E.weight.resize(static_cast<size_t>(n) * hk);
  return static_cast<bool>(f.read(reinterpret_cast<char*>(E.weight.data()),
                                  static_cast<std::streamsize>(E.weight.size() * sizeof(double))));
}

void write_exact(const std::string& path, int32_t n, std::span<const int32_t> ids, const SkinningWeights& E) {
  if (path.empty()) return;
  std::ofstream f(path, std::ios::binary);
  const int32_t k = static_cast<int32_t>(ids.size());
  f.write(reinterpret_cast<const char*>(&n), 4);
  f.write(reinterpret_cast<const char*>(&k), 4);
  f.write(reinterpret_cast<const char*>(ids.data()), 4 * static_cast<std::streamsize>(k));
  f.write(reinterpret_cast<const char*>(E.weight.data()), static_cast<std::streamsize>(E.weight.size() * sizeof(double)));
}

int run_skinning(const cli::CommonOptions& opt, const SkinningBenchOptions& o, const RunContext& ctx) {
  if (o.repeats < 1) fail(ErrorCode::BadUsage, "skinning: --repeats must be at least 1");
  const cli::Input in = cli::load_input(opt, ctx);
  const Mesh& m = in.mesh;
  const std::vector<int32_t> ids = bench_handles(opt, o, m);
  cli::vertex_sites(m, "--handle-ids", ids);  // range check
  std::vector<std::vector<int32_t>> handles;
  for (int32_t v : ids) handles.push_back({v});
  cli::Stopwatch sw;
  const bool fine = !o.coarse_only;
  const HeatDiffusion H = fine ? prepare_heat_diffusion(m, o.t_factor, 0.0, ctx) : HeatDiffusion{};  // as `locus skinweights`
  const double factor_s = sw.seconds();
  const Adjacency adj = vertex_adjacency(m);
  Json j{{"command", "skinning"}, {"input", cli::input_json(opt, in)}, {"n", m.num_vertices()}, {"handles", ids},
         {"factor_s", factor_s}, {"threads", ctx.threads}};
  const bool run_exact = fine && m.num_vertices() <= o.exact_max_vertices;
  SkinningWeights exact;
  if (run_exact && read_exact(o.exact_cache, m.num_vertices(), ids, exact)) {
    j["exact"] = {{"cached", o.exact_cache}, {"properties", properties(m, exact, ids)}, {"roughness", roughness(adj, exact)}};
  } else if (run_exact) {
    SkinningOptions so;
    so.method = SkinningMethod::Exact;
    sw.restart();
    exact = skinning_weights(H, m, handles, so, ctx);
    const double s = sw.seconds();
    j["exact"] = {{"wall_s", s}, {"with_factor_s", s + factor_s}, {"repeats", 1}, {"properties", properties(m, exact, ids)},
                  {"roughness", roughness(adj, exact)}, {"degenerate_rows", exact.degenerate},
                  {"max_clamped", exact.max_clamped}};
    write_exact(o.exact_cache, m.num_vertices(), ids, exact);
  }
  Json sampled = Json::array(), coarse = Json::array();
  for (const std::string& text : cli::split_commas(o.samples)) {
    // The coarse road (skinning_coarse.hpp: `locus skinweights` on large meshes):
    // its own coarse operator, timed with it; the fine mesh's factor is not used.
    SkinningOptions co;
    co.samples = std::stoi(text);
    std::vector<double> cwall;
    SkinningWeights C;
    for (int32_t r = 0; r < o.repeats; ++r) {
      sw.restart();
      C = skinning_weights_coarse(m, handles, co, o.t_factor, 0.0, ctx);
      cwall.push_back(sw.seconds());
    }
    Json crow{{"samples_target", co.samples}, {"samples", C.samples}, {"coarse_vertices", C.coarse_vertices},
              {"wall_s", cli::median(cwall)}, {"wall_s_all", cwall},
              {"phase_s", {{"level", C.prepare_s}, {"factor", C.factor_s}, {"coarse_weights", C.weights_s},
                           {"propagate", C.propagate_s}}},
              {"properties", properties(m, C, ids)}};
    if (run_exact) compare(m, adj, C, exact, crow);
    coarse.push_back(crow);
    if (!fine) continue;
    SkinningOptions so;
    so.samples = std::stoi(text);
    so.exact_up_to = o.exact_up_to;
    std::vector<double> wall;
    SkinningWeights W;
    for (int32_t r = 0; r < o.repeats; ++r) {
      sw.restart();
      W = skinning_weights(H, m, handles, so, ctx);
      wall.push_back(sw.seconds());
    }
    const double med = cli::median(wall);
    Json row{{"samples_target", so.samples}, {"method", W.method}, {"samples", W.samples},   {"refined", W.refined}, {"sample_rings", W.sample_rings},
             {"wall_s", med},                {"with_factor_s", med + factor_s}, {"wall_s_all", wall},
             {"phase_s", {{"prepare", W.prepare_s}, {"exact_rows", W.weights_s}, {"propagate", W.propagate_s}}},
             {"properties", properties(m, W, ids)}};
    if (run_exact) compare(m, adj, W, exact, row);
    if (run_exact && !o.vertex_csv.empty()) write_vertex_csv(o.vertex_csv, m, adj, W, exact);
    if (run_exact && o.worst > 0) row["worst"] = worst_vertices(m, adj, W, exact, o.worst);
    sampled.push_back(row);
  }
  j["sampled"] = sampled;
  j["coarse"] = coarse;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

}  // namespace

void register_skinning_bench(cli::CommandTable& table) {
  auto o = std::make_shared<SkinningBenchOptions>();
  CLI::App* app = table.add("skinning", "Skinning weights: sampled vs exact natural-neighbor weights, timings and properties",
                            [o](const cli::CommonOptions& opt, const RunContext& ctx) { return run_skinning(opt, *o, ctx); });
  app->add_option("--handles", o->handles, "Number of handles (default 4)");
  app->add_option("--handle-ids", o->handle_ids, "Handle vertex ids, comma-separated (overrides --handles)");
  app->add_option("--samples", o->samples, "Sampled method: comma-separated sample targets (default 1024)");
  app->add_option("--repeats", o->repeats, "Timed runs of each sampled setting (median; default 3)");
  app->add_option("--exact-max-vertices", o->exact_max_vertices,
                  "Run the exact method only up to this many vertices (default 30000)");
  app->add_flag("--coarse-only", o->coarse_only,
               "Only the coarse road (no fine factorization, sampled or exact run: meshes too large for them)");
  app->add_option("--t-factor", o->t_factor, "Diffusion time in units of h^2 (default 1, as skinweights' default --t h2)");
  app->add_option("--worst", o->worst, "List this many vertices of the largest |w - w_exact| with their surroundings");
  app->add_option("--vertex-csv", o->vertex_csv, "Per-vertex features and |w - w_exact| into this CSV file");
  app->add_option("--exact-up-to", o->exact_up_to,
                  "Sampled: meshes of at most this many vertices take exact rows everywhere (default 10000; 0: "
                  "only by the sample target)");
  app->add_option("--exact-cache", o->exact_cache,
                  "File of the exact weights: read when it matches the mesh and handles, else computed and written");
}

}  // namespace locus::bench
