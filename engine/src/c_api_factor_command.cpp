// The C API of the factor command (locus_commands.h, locus_factor_options):
// the C options translated to the engine's request (engine/include/locus/
// engine/factor_request.hpp), run by the Session, the solution and the report
// copied out.
#include <algorithm>
#include <cstring>
#include <string>

#include "c_api_support.hpp"
#include "locus/engine/factor_request.hpp"

using namespace locus::c_api_detail;

extern "C" {

locus_factor_options locus_factor_options_default(void) {
  const locus::FactorCommandRequest d;
  locus_factor_options o;
  std::memset(&o, 0, sizeof o);
  o.repeat = d.repeat;
  o.seed = d.seed;
  return o;  // matrix NULL: the request's "heat"; t NULL: h^2
}

locus_status locus_factor_run(locus_session* session, const locus_factor_options* options, double* out_x,
                              locus_factor_report* out_report, const locus_run_options* opts) {
  return guarded("locus_factor_run", [&] {
    locus::Session& s = session_of(session);
    require(options != nullptr, "options is NULL");
    CallContext cc(opts);
    no_run_time(cc);
    locus::FactorCommandRequest q;
    if (options->matrix && options->matrix[0]) q.matrix = options->matrix;
    if (options->t) q.t = options->t;
    q.repeat = options->repeat;
    if (options->save) q.save = options->save;
    if (options->load) q.load = options->load;
    q.seed = options->seed;
    const locus::FactorCommandReport r = s.factor(q, cc.ctx);
    if (out_x) std::copy(r.x.begin(), r.x.end(), out_x);
    if (!out_report) return;
    locus_factor_report& o = *out_report;
    std::memset(&o, 0, sizeof o);
    o.n = r.n, o.repeats = r.repeats;
    o.nnz_A = r.nnz_A, o.nnz_L = r.nnz_L, o.nnz_L_exact = r.nnz_L_exact;
    o.supernodes = r.supernodes, o.etree_height = r.etree_height, o.super_etree_height = r.super_etree_height;
    o.flops = r.flops;
    o.t = r.t, o.h = r.h;
    o.residual = r.residual, o.residual8 = r.residual8, o.lane0_vs_solve = r.lane0_vs_solve;
    o.operator_s = r.operator_s, o.order_s = r.order_s, o.symbolic_s = r.symbolic_s, o.numeric_s = r.numeric_s;
    o.solve_s = r.solve_s, o.solve8_s = r.solve8_s;
    o.load_s = r.factor_cache.load_s, o.save_s = r.factor_cache.save_s;
  });
}

}  // extern "C"
