// Internals of locus::Session shared by its source files (engine/src/session*.cpp,
// one per pipeline family): the build-once caches, the per-positions State and
// the helpers that fetch cached operators. Not installed.
//
// Concurrency design. The mesh and its position-dependent caches live in an
// immutable-after-construction State held by shared_ptr; set_positions()
// builds a new State and swaps the pointer under a mutex, so a running query
// keeps its State alive and never sees a half-updated mesh. Inside a State every
// cache is a OnceMap: key -> shared_future of an immutable value. The first
// thread to ask for a key builds it outside the lock; the others wait on the
// future (polling their own cancel flag). Failures that depend on the caller
// (cancellation, memory limit, allocation failure) are not cached: the entry is
// removed and the next caller builds again; deterministic failures (a mesh that
// is not positive definite) are cached like values.
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <future>
#include <map>
#include <optional>
#include <string>
#include <memory>
#include <mutex>
#include <new>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "locus/engine/factor_store.hpp"
#include "locus/error.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/operator_choice.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "locus/session.hpp"

namespace locus {

struct SheetsSession;  // sheets_session.hpp

// choose_operator (operator_choice.hpp) on the edge incidence and one-pass
// report the Session's check already made (engine/src/operator_choice.cpp).
OperatorReport choose_operator_from(const Mesh& m, const EdgeIncidence& inc, const MeshReport& report,
                                    OperatorChoice choice);

namespace session_detail {

inline bool transient_failure(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const Error& err) {
    return err.code() == ErrorCode::Cancelled || err.code() == ErrorCode::ResourceLimit;
  } catch (const std::bad_alloc&) {
    return true;
  } catch (...) {
    return false;
  }
}

// Build-once map: concurrent callers of get() for one key share one build.
template <class K, class V>
class OnceMap {
 public:
  template <class Build>
  std::shared_ptr<const V> get(const K& key, const RunContext& ctx, Build&& build) {
    for (;;) {
      std::promise<std::shared_ptr<const V>> promise;
      std::shared_future<std::shared_ptr<const V>> fut;
      bool owner = false;
      {
        std::lock_guard<std::mutex> lock(mu_);
        auto it = map_.find(key);
        if (it == map_.end()) {
          fut = promise.get_future().share();
          map_.emplace(key, fut);
          owner = true;
        } else {
          fut = it->second;
        }
      }
      if (owner) {
        try {
          promise.set_value(build());
        } catch (...) {
          const std::exception_ptr e = std::current_exception();
          if (transient_failure(e)) {  // erase first: waiters that retry must not find this entry
            std::lock_guard<std::mutex> lock(mu_);
            map_.erase(key);
          }
          promise.set_exception(e);
        }
        return fut.get();
      }
      while (fut.wait_for(std::chrono::milliseconds(5)) != std::future_status::ready) ctx.check_cancel();
      try {
        return fut.get();
      } catch (...) {
        // The builder's cancel flag or memory limit is not ours: build again with ours.
        if (!transient_failure(std::current_exception())) throw;
        ctx.check_cancel();
      }
    }
  }

  // True when the key is built or being built (progress weights: a cached build costs nothing).
  bool contains(const K& key) {
    std::lock_guard<std::mutex> lock(mu_);
    return map_.count(key) != 0;
  }

 private:
  std::mutex mu_;
  std::map<K, std::shared_future<std::shared_ptr<const V>>> map_;
};

// One monotone progress fraction per Session call: the
// cached operators the call has to build take [0, build_share) of it (none
// when they are cached: the first query at 416k vertices is ~97% factoring,
// docs/shipping.md), the query itself the rest. Reports through either never
// go below an earlier one of the call (worker threads' reports may arrive out
// of order), and finish() reports 1.
class CallProgress {
 public:
  static constexpr double kBuildShare = 0.9;
  CallProgress(const RunContext& ctx, bool builds, double build_share = kBuildShare) : base_(ctx) {
    if (ctx.progress) {
      auto clamp = std::make_shared<Clamp>();
      base_.progress = [clamp, out = ctx.progress](double f, std::string_view phase) {
        std::lock_guard<std::mutex> lock(clamp->mu);
        f = std::min(1.0, std::max(f, clamp->last));
        clamp->last = f;
        out(f, phase);
      };
    }
    const double share = builds ? build_share : 0.0;
    build_ = base_.sub(0.0, share);
    query_ = base_.sub(share, 1.0);
  }
  const RunContext& build() const { return build_; }
  const RunContext& query() const { return query_; }
  void finish(std::string_view phase) const { query_.report(1.0, phase); }

 private:
  struct Clamp {
    std::mutex mu;
    double last = 0.0;
  };
  RunContext base_, build_, query_;
};

inline uint64_t bits_of(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// HeatQuery::t_factor 0 = the method's default (session.hpp): the same as
// the CLI's and the pipelines' (HeatGeodesicOptions, 1 for diffusion).
inline double heat_method_t_factor(const HeatQuery& q) {
  return q.t_factor == 0.0 ? HeatGeodesicOptions{}.t_factor : q.t_factor;
}
inline double diffusion_t_factor(const HeatQuery& q) { return q.t_factor == 0.0 ? 1.0 : q.t_factor; }

struct Counters {
  std::atomic<int64_t> symbolic{0}, numeric{0}, engines{0}, deform{0};
};

// Symbolic factors depend on the sparsity pattern only: shared by every State of a Session.
struct SymbolicCache {
  OnceMap<std::pair<uint64_t, int64_t>, SymbolicFactor> by_pattern;  // (pattern hash, nnz)
};

// -L_C + eps M of the mesh and its factor (the global operator of the patch parameterizations).
struct RegularizedLaplacian {
  CscMatrix K;
  NumericFactor factor;
};

// The polygon log map's patches: the Dijkstra disk over the polygon edges (as `locus logmap`).
struct PolygonPatches {
  Adjacency adjacency;
  HostVector<double> edge_length;
};

struct State {
  Mesh mesh;                             // triangles (a polygon mesh's triangulation)
  std::shared_ptr<const Mesh> polygons;  // a polygon mesh as given, same positions; null for triangle meshes
  std::shared_ptr<const MeshDerived> derived;  // edges, adjacency, h, mass, components: once per positions
  double h = 0;                                // derived->h
  int64_t version = 0;
  std::shared_ptr<SymbolicCache> symbolic;
  std::shared_ptr<Counters> counters;
  OnceMap<uint64_t, HeatLogMap> engines;                             // t_factor bits
  OnceMap<int, DeformOperator> deform_ops;                           // energy
  OnceMap<int, PatchGrower> grower;                                  // single entry: log map patches
  OnceMap<int, HeatDiffusion> cvt_heat;                              // single entry: M - h^2 L for CVT cells
  // The diffusion, shape and Voronoi pipelines (session_<pipeline>.cpp):
  OnceMap<uint64_t, HeatDiffusion> diffusion;  // absolute t bits: M - tL (diffusion pipelines, heat values)
  OnceMap<int, RegularizedLaplacian> laplacian;  // single entry: -L + eps M (patch parameterization)
  // Polygon meshes (session_polygon.cpp): the polygon heat method per t_factor
  // (its geodesic() serves geodesic_distance), the log map's patches.
  OnceMap<uint64_t, PolygonLogMap> polygon_engines;  // t_factor bits
  OnceMap<int, PolygonPatches> polygon_patches;      // single entry
  OnceMap<int, DemLogMap> dem;                       // single entry: the DEM log map (logmap method dem)
  // The robust operator (engine/include/locus/engine/operator_choice.hpp): when
  // `robust`, every Laplacian, mass matrix and heat-method engine of this State
  // comes from robust_ops (built once per positions) instead of the cotan operator.
  bool robust = false;
  OnceMap<int, RobustOperators> robust_ops;          // single entry
  OnceMap<uint64_t, HeatGeodesic> robust_engines;    // t_factor bits: the heat method on the intrinsic triangles
  OnceMap<int, SheetsSession> sheets;                // single entry: a defective mesh's manifold sheets (log map, deform)
};

// Checks the mesh (once per positions) and derives its data; d.checked records the check.
// With `choice` auto or robust the defects are looked for in the same pass
// (`report`); a mesh the robust operator takes is then checked only for what
// every operator needs (triangles, finite coordinates, a face).
std::shared_ptr<const MeshDerived> check_and_derive(const Mesh& m, OperatorChoice choice = OperatorChoice::Cotan,
                                                    OperatorReport* report = nullptr);
// The robust Laplacian and mass of s.mesh, built once per positions.
std::shared_ptr<const RobustOperators> robust_operators(State& s, const RunContext& ctx);
// The heat method's distance engine for q.t_factor: the log map engine's
// HeatGeodesic (cotan), or one on the robust operator's intrinsic triangles.
std::shared_ptr<const HeatGeodesic> geodesic_engine(State& s, const HeatQuery& q, const RunContext& ctx);
bool geodesic_engine_cached(State& s, const HeatQuery& q);
// The heat method on the robust operator's intrinsic triangles, whatever the
// session's operator (auto's fallback when the cotan heat method fails).
std::shared_ptr<const HeatGeodesic> robust_geodesic_engine(State& s, const HeatQuery& q, const RunContext& ctx);
// Per vertex of s.mesh, whether a face uses it; empty when every vertex is
// (always on the cotan operator, which refuses unreferenced vertices). Values
// at an unreferenced vertex are NaN (no value), as in every output format.
std::vector<char> referenced_vertices(const State& s);
// BadUsage naming `what` unless v is a vertex of s.mesh.
void check_vertex(const State& s, int64_t v, const char* what);
void check_t_factor(double t_factor);
// check_t_factor, and BadUsage when q asks for an absolute t (the heat method scales t by h^2).
void check_heat_method_time(const HeatQuery& q, double t_factor);
// Numerical, naming the vertex, unless the log map's (u, v) are finite on the whole patch.
void check_map_finite(int32_t center, const LogMapResult& r);
// The heat-method engine (geodesic distance and log maps) for q.t_factor.
std::shared_ptr<const HeatLogMap> engine(State& s, const HeatQuery& q, const RunContext& ctx);
// The symbolic factor of A's pattern (shared by every State of the Session).
std::shared_ptr<const SymbolicFactor> symbolic_for(State& s, const CscMatrix& A, const RunContext& ctx);
// Log map and patch-parameterization patches (patch_grower.hpp), on the derived adjacency.
std::shared_ptr<const PatchGrower> grower(State& s, const RunContext& ctx);

// The heat operator M - tL, t = q.t when > 0, else q.t_factor * h^2, factored once per t
// (the ordering of prepare_heat_diffusion, so the factor is bit-identical to the CLI's).
std::shared_ptr<const HeatDiffusion> diffusion(State& s, const HeatQuery& q, const RunContext& ctx);
// True when diffusion(s, q) is cached (or being built): a call then has nothing to build.
bool diffusion_cached(State& s, const HeatQuery& q);
// -L_C + eps M (mesh_operators regularized_laplacian, default eps), factored once.
std::shared_ptr<const RegularizedLaplacian> laplacian(State& s, const RunContext& ctx);
// BadUsage unless p is a vertex or a face with valid barycentric weights; returns the kernel's point.
SurfacePoint surface_point(const State& s, const MeshPoint& p, const char* what, size_t index);
std::vector<SurfacePoint> surface_points(const State& s, ConstView<MeshPoint> p, const char* what);
void check_vertices(const State& s, ConstView<int32_t> v, const char* what);

// ---- Polygon meshes (session_polygon.cpp) ----
// The triangulation of a polygon mesh for the Session (BadInput naming a face
// that is no simple polygon); `face_of`: per triangle, its polygon.
Mesh triangulate_for_session(const Mesh& polygons, std::vector<int32_t>& face_of);
// The polygon faces with new positions, checked again as simple polygons.
std::shared_ptr<const Mesh> polygons_moved(const Mesh& polygons, const Mesh& moved);
// t_factor of the polygon heat method: q.t_factor, 0 = PolygonHeatGeodesicOptions' default (8).
double polygon_t_factor(const HeatQuery& q);
std::shared_ptr<const PolygonLogMap> polygon_engine(State& s, const HeatQuery& q, const RunContext& ctx);
// Whole-mesh distance from one vertex (PolygonHeatGeodesic::query_full), NaN in other components.
void polygon_geodesic(State& s, int32_t source, View<double> out, const HeatQuery& q, const RunContext& ctx);
// From a set of sources: the heat of all at once, shifted per component as the triangle path.
void polygon_geodesic(State& s, std::span<const SurfacePoint> sources, View<double> out, const HeatQuery& q,
                      const RunContext& ctx);
LogMapResult polygon_logmap(State& s, int32_t center, int32_t count, const HeatQuery& q, const RunContext& ctx);

// ---- The heat-method commands (session_geodesic_command.cpp, session_logmap_command.cpp) ----
double seconds_since(std::chrono::steady_clock::time_point t0);
// Error(BadUsage) unless 0 < fraction <= 1.
void check_fraction(double fraction);
// A request's diffusion time (t or t_factor; default 4h2).
HeatTime heat_method_time(const std::string& t, const std::optional<double>& t_factor);
// The heat-method engine for t_factor: the Session's cached one, or with a
// factor cache (save/load) one of the caller's own, its factors loaded or saved.
std::shared_ptr<const HeatLogMap> heat_method_engine(State& s, double t_factor, const FactorCacheFiles& files,
                                                     FactorCacheReport& report, const RunContext& ctx);
// "the heat underflowed at N<what>--t Ch2 (t = T) avoids it".
std::string underflow_warning(int64_t vertices, double t_no_underflow, double h, const char* what);

}  // namespace session_detail

// What factoring the cells' operator costs, in Lloyd iterations (measured,
// docs/shipping.md): its weight in cvt's progress.
inline constexpr double kCvtFactorIterations = 2.2;

// The cvt command's call sequence after its checks (session_cvt_command.cpp):
// Lloyd and the remesh on `prepared` (the cells' M - tL; null: cvt_lloyd
// factors its own), and the statistics. Session::cvt(const CvtRequest&) and
// the cached tier (Session::cvt with remesh) both run it.
// `operator_done`: RemeshOptions::operator_done (the owner of `prepared` frees it).
// `lloyd_done`: RemeshOptions::lloyd_done (the owner of `derived` restores what it freed).
// `corners_needed`: RemeshOptions::corners_needed (the owner of `mesh` restores its corners).
CvtReport run_cvt(const Mesh& mesh, const MeshDerived& derived, const CvtRequest& req, const HeatTime& ts,
                  const HeatTime& tc, const HeatDiffusion* prepared, const RunContext& ctx,
                  std::function<void()> operator_done = {}, std::function<void()> lloyd_done = {},
                  std::function<void()> corners_needed = {});

// The cvt request's sites on this mesh: BadInput for more than its vertices;
// fewer than its components are raised to their count (and ctx notes it).
int32_t check_sites(const CvtRequest& req, const Mesh& mesh, const MeshDerived& derived, int32_t components,
                    bool remesh, const RunContext& ctx);

// The cached tier's result (CvtResult: the remesh as arrays) from the command's report.
CvtResult cvt_result_of(CvtReport&& c);

struct Session::Impl {
  mutable std::mutex mu;  // guards `state` (the pointer, not what it points to)
  std::shared_ptr<session_detail::State> state;
  int32_t nv = 0, nf = 0;
  int32_t components = 0;  // connectivity never changes
  int32_t npoly = 0;       // faces as given (polygon meshes; nf otherwise)
  std::vector<int32_t> face_of;  // polygon meshes: per triangle its face as given; empty otherwise
  int64_t polygon_edges = 0;     // polygon meshes: unique edges of the faces as given
  OperatorReport op;             // the operator chosen at construction, and why
  bool robust_fallback = false;  // auto chose cotan: a failing cotan heat method falls back to robust
  bool exclusive = false;        // SessionOptions::exclusive

  std::shared_ptr<session_detail::State> current() const {
    std::lock_guard<std::mutex> lock(mu);
    return state;
  }
};

}  // namespace locus
