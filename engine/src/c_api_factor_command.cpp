// The C API of the factor command (locus_commands.h, locus_factor_options):
// the C options translated to the engine's request (engine/include/locus/
// engine/factor_request.hpp), run by the Session, the solution and the report
// copied out.
#include <algorithm>
#include <cstring>
#include <string>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/factor_request.hpp"

using namespace locus::c_api_detail;

extern "C" {

locus_factor_options locus_factor_options_default(void) {
  // matrix NULL: the request's "heat"; t NULL: h^2
  return LOCUS_C_DEFAULTS(locus_factor_options, locus::FactorCommandRequest, repeat, seed);
}

locus_status locus_factor_run(locus_session* session, const locus_factor_options* options, double* out_x,
                              locus_factor_report* out_report, const locus_run_options* opts) {
  return command_run("locus_factor_run", session, options, {}, opts, [&](locus::Session& s, CallContext& cc) {
    locus::FactorCommandRequest q;
    LOCUS_COPY_FIELDS(q, *options, repeat, seed, matrix, t, save, load);
    const locus::FactorCommandReport r = s.factor(q, cc.ctx);
    if (out_x) std::copy(r.x.begin(), r.x.end(), out_x);
    report_into(out_report, [&](locus_factor_report& o) {
      LOCUS_COPY_FIELDS(o, r, n, repeats, nnz_A, nnz_L, nnz_L_exact, supernodes, etree_height, super_etree_height,
                        flops, t, h, residual, residual8, lane0_vs_solve, operator_s, order_s, symbolic_s, numeric_s,
                        solve_s, solve8_s);
      o.load_s = r.factor_cache.load_s, o.save_s = r.factor_cache.save_s;
    });
  });
}

}  // extern "C"
