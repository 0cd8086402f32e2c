// `heat` as every front end runs it (engine/include/locus/engine/
// diffusion_requests.hpp): pairwise heat exchange of thesis §4.6
// (pipelines/.../heat/heat_exchange.hpp): unit heat at every source, one
// backward-Euler step with M - tL (the Session's operator, cotan or robust,
// operator_choice.hpp), the heat at each target, with the command's own
// factor (factor_or_load, as adf and hks) and the query repeated for median
// timings.
#include <algorithm>
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
#include "locus/pipelines/heat/heat_exchange.hpp"
#include "locus/session.hpp"
#include "session_state.hpp"

namespace locus {
namespace session_detail {

double diffusion_mesh_h(const State& s);  // session_heat_signature_command.cpp
CscMatrix command_heat_operator(State& s, double t, const RunContext& ctx);
void check_ids_sign(const std::vector<int64_t>& ids, const char* what);
std::vector<int32_t> vertex_ids(const State& s, const std::vector<int64_t>& ids, const char* what);

namespace {

using command_clock::median_of;

using command_clock::seconds;

}  // namespace
}  // namespace session_detail

using namespace session_detail;

void check_request(const HeatRequest& req) {
  parse_heat_exchange_method(req.method);
  parse_heat_time(req.t, "--t");
  if (req.source.empty() || req.target.empty())
    fail(ErrorCode::BadUsage, "heat: the source and target sets must not be empty");
  check_ids_sign(req.source, "--source");
  check_ids_sign(req.target, "--target");
  if (req.repeat < 1 || req.repeat > 100000)
    fail(ErrorCode::BadUsage, "repeat must be in 1..100000 (got " + std::to_string(req.repeat) + ")");
  check_factor_cache_files({req.save, req.load});
}

HeatReport Session::heat(const HeatRequest& req, const RunContext& ctx) const {
  check_request(req);
  const std::shared_ptr<State> s = impl_->current();
  const Mesh& m = s->mesh;
  HeatReport r;
  const HeatExchangeMethod method = parse_heat_exchange_method(req.method);
  r.method = heat_exchange_method_name(method);
  r.h = diffusion_mesh_h(*s);
  r.n = m.num_vertices();
  r.sources = vertex_ids(*s, req.source, "--source: vertex");
  r.targets = vertex_ids(*s, req.target, "--target: vertex");
  r.t = parse_heat_time(req.t, "--t").resolve(r.h);
  r.t_spec = req.t;
  r.repeats = req.repeat;

  auto t0 = std::chrono::steady_clock::now();
  const CscMatrix A = command_heat_operator(*s, r.t, ctx);
  r.operator_s = seconds(t0);
  const FactorRequest freq{"heat", r.t, &A};
  const FactorCacheFiles files{req.save, req.load};
  const Factors H = factor_or_load(files, m, std::span(&freq, 1), ctx);
  LOCUS_COPY_FIELDS(r, H, order_s, analyze_s, numeric_s);
  r.factor_cache = FactorCacheReport{req.load, req.save, H.load_s, H.save_s};
  r.nnz_L = H.symbolic->nnz_L;
  r.etree_height = H.symbolic->etree_height;
  HeatWorkspace ws;
  r.values.resize(r.targets.size());
  std::vector<double> query_s, plan_s, solve_s;
  HeatExchangeStats st;
  for (int r_ = 0; r_ < req.repeat; ++r_) {
    ctx.check_cancel();
    t0 = std::chrono::steady_clock::now();
    locus::heat_exchange(H.factors[0], r.sources, r.targets, method, r.values, ws, &st);
    query_s.push_back(seconds(t0));
    plan_s.push_back(st.plan_s);
    solve_s.push_back(st.solve_s);
  }
  const std::vector<char> used = referenced_vertices(*s);
  for (size_t k = 0; k < r.values.size(); ++k) {
    if (!used.empty() && !used[r.targets[k]]) {
      r.values[k] = std::numeric_limits<double>::quiet_NaN();  // no face: no value
      continue;
    }
    if (!std::isfinite(r.values[k]))
      fail(ErrorCode::Numerical,
           "heat: the value at target " + std::to_string(r.targets[k]) + " is " + format_number(r.values[k]));
    r.total += r.values[k];
  }
  r.forward_columns = st.forward_columns;
  r.backward_columns = st.backward_columns;
  r.query_s = median_of(query_s);
  r.plan_s = median_of(plan_s);
  r.solve_s = median_of(solve_s);
  return r;
}

}  // namespace locus
