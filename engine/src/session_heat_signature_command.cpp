// `adf` and `hks` as every front end runs them (engine/include/locus/engine/
// diffusion_requests.hpp): the auto-diffusion values (M - t L_C)^{-1}_ii of
// thesis §4.6 for one or several t (pipelines/.../heat/adf.hpp), with one
// ordering and one symbolic factor shared by every t, on the Session's
// operator (cotan or robust, operator_choice.hpp).
//
// The factors are the command's own (factor_or_load: ordered, analyzed and
// factored, or read from the request's `load`; written to `save`), not the
// Session's cache, so that the report carries the phases' sizes and times the
// CLI has always printed and the values equal, bit for bit, a file's factors.
// Session::heat_kernel_signature is the cached tier.
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "command_clock.hpp"
#include "field_copy.hpp"
#include "locus/engine/diffusion_requests.hpp"
#include "locus/engine/factor_store.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"
#include "locus/pipelines/heat/adf.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {

// The mesh checks of the local-solve commands (adf, hks, heat); the mean edge
// length. On the robust operator the mesh needs only triangles and finite
// coordinates (its defects are what that operator is for).
double diffusion_mesh_h(const State& s) {
  const Mesh& m = s.mesh;
  const std::string where = m.source.empty() ? std::string("the mesh") : m.source;
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, where + " has no faces");
  MeshRequirements req;
  if (s.robust) req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = false;
  check_requirements(m, req);
  const double h = mean_edge_length(m);
  if (!(h > 0) || !std::isfinite(h)) fail(ErrorCode::BadInput, where + ": mean edge length is " + format_number(h));
  return h;
}

// M - tL of the Session's operator: the cotan one of the mesh's triangles or
// the robust one (operator_choice.hpp; its Laplacian built once per positions).
CscMatrix command_heat_operator(State& s, double t, const RunContext& ctx) {
  if (!s.robust) return heat_operator(s.mesh, t);
  return robust_heat_operator(*robust_operators(s, ctx), t);
}

// Vertex ids of a request: negative ones are bad usage before any mesh is read.
void check_ids_sign(const std::vector<int64_t>& ids, const char* what) {
  for (int64_t v : ids)
    if (v < 0) fail(ErrorCode::BadUsage, std::string(what) + ": vertex " + std::to_string(v) + " is negative (ids are 0-based)");
}

std::vector<int32_t> vertex_ids(const State& s, const std::vector<int64_t>& ids, const char* what) {
  std::vector<int32_t> out;
  out.reserve(ids.size());
  for (int64_t v : ids) {
    check_vertex(s, v, what);
    out.push_back(static_cast<int32_t>(v));
  }
  return out;
}

namespace {

struct SignatureArgs {
  const char* command;  // "adf" or "hks"
  const std::vector<std::string>& ts;
  const std::vector<int64_t>& vertices;
  bool all;
  const std::string& method;
  FactorCacheFiles files;
};

void check_signature_args(const SignatureArgs& a) {
  const std::string who = a.command;
  parse_adf_method(a.method);
  if (a.ts.empty()) fail(ErrorCode::BadUsage, who + ": no diffusion time given");
  for (const std::string& t : a.ts) parse_heat_time(t, "--t");
  if (a.all == !a.vertices.empty())
    fail(ErrorCode::BadUsage, who + ": give exactly one of --vertices LIST or --all");
  check_ids_sign(a.vertices, "--vertices");
  check_factor_cache_files(a.files);
}

using command_clock::seconds;

HeatSignatureReport signature(State& s, const SignatureArgs& a, const RunContext& ctx) {
  check_signature_args(a);
  const std::string who = a.command;
  const Mesh& m = s.mesh;
  HeatSignatureReport r;
  r.method = adf_method_name(parse_adf_method(a.method));
  r.h = diffusion_mesh_h(s);
  r.n = m.num_vertices();
  r.all = a.all;
  r.t_spec = a.ts;
  for (const std::string& t : a.ts) r.t.push_back(parse_heat_time(t, "--t").resolve(r.h));
  r.vertices = vertex_ids(s, a.vertices, "--vertices: vertex");
  ctx.check_cancel();

  // One heat operator per t on one pattern: factored (one ordering, one symbolic factor) or loaded.
  HeatFactors H;
  H.t = r.t;
  auto t0 = std::chrono::steady_clock::now();
  std::vector<CscMatrix> A;
  for (double t : r.t) {
    if (!(std::isfinite(t) && t > 0))
      fail(ErrorCode::BadUsage, who + ": diffusion time " + format_number(t) + " must be finite and > 0");
    A.push_back(command_heat_operator(s, t, ctx));
  }
  r.operator_s = seconds(t0);
  std::vector<FactorRequest> req;
  for (size_t k = 0; k < r.t.size(); ++k) req.push_back({"heat", r.t[k], &A[k]});
  Factors F = factor_or_load(a.files, m, req, ctx);
  H.symbolic = F.symbolic;
  H.factors = std::move(F.factors);
  LOCUS_COPY_FIELDS(r, F, order_s, analyze_s, numeric_s);
  r.factor_cache = FactorCacheReport{a.files.load, a.files.save, F.load_s, F.save_s};
  r.nnz_L = H.symbolic->nnz_L;
  r.supernodes = H.symbolic->ns;
  r.etree_height = H.symbolic->etree_height;

  const size_t nt = r.t.size();
  const size_t count = a.all ? static_cast<size_t>(r.n) : r.vertices.size();
  r.values.resize(count * nt);
  t0 = std::chrono::steady_clock::now();
  heat_kernel_signature(H, r.vertices, parse_adf_method(a.method), r.values, ctx);
  r.query_s = seconds(t0);
  const std::vector<char> used = referenced_vertices(s);
  for (size_t k = 0; k < r.values.size(); ++k) {
    const int32_t v = a.all ? static_cast<int32_t>(k / nt) : r.vertices[k / nt];
    if (!used.empty() && !used[v]) {
      r.values[k] = std::numeric_limits<double>::quiet_NaN();  // no face: no value
      continue;
    }
    if (!(std::isfinite(r.values[k]) && r.values[k] > 0)) {
      fail(ErrorCode::Numerical, who + ": the value at vertex " + std::to_string(v) + " for t = " +
                                     format_number(r.t[k % nt]) + " is " + format_number(r.values[k]) +
                                     "; the heat operator is numerically singular");
    }
  }
  return r;
}

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void check_request(const AdfRequest& req) {
  const std::vector<std::string> ts{req.t};
  check_signature_args({"adf", ts, req.vertices, req.all, req.method, {req.save, req.load}});
}

void check_request(const HksRequest& req) {
  check_signature_args({"hks", req.ts, req.vertices, req.all, req.method, {req.save, req.load}});
}

HeatSignatureReport Session::adf(const AdfRequest& req, const RunContext& ctx) const {
  const std::vector<std::string> ts{req.t};
  return signature(*impl_->current(), {"adf", ts, req.vertices, req.all, req.method, {req.save, req.load}}, ctx);
}

HeatSignatureReport Session::hks(const HksRequest& req, const RunContext& ctx) const {
  return signature(*impl_->current(), {"hks", req.ts, req.vertices, req.all, req.method, {req.save, req.load}}, ctx);
}

}  // namespace locus
