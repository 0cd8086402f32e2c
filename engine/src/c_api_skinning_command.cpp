// The C API of the skinweights command (locus_commands.h,
// locus_skinweights_options): the C options translated to the engine's request
// (engine/include/locus/engine/skinning_requests.hpp), run by the Session, the
// weights and report copied out. Handles as vertex sets (offsets into one id
// array) and bones (offsets into one point array); every check beyond C's own
// (NULL arrays, ascending offsets) is the Session's.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/skinning_requests.hpp"

using namespace locus::c_api_detail;

extern "C" {

locus_skinweights_options locus_skinweights_options_default(void) {
  locus_skinweights_options o;
  std::memset(&o, 0, sizeof o);
  return o;
}

// C++ helpers of the C functions around them: C++ language linkage, as they
// return C++ types.
extern "C++" {
namespace {

locus::SkinningRequest skinning_request_of(const locus_skinweights_options& o) {
  locus::SkinningRequest q;
  require(o.n_handles >= 0 && o.n_bones >= 0, "n_handles and n_bones must be >= 0");
  require(o.n_handles == 0 || o.handles != nullptr, "handles is NULL");
  for (int64_t i = 0; i < o.n_handles; ++i) {
    const int64_t a = o.handle_offsets ? o.handle_offsets[i] : i, b = o.handle_offsets ? o.handle_offsets[i + 1] : i + 1;
    require(a >= 0 && b >= a, "handle_offsets are not ascending");
    require(b - a <= kMaxVertices, "a handle has too many vertices");
    q.handles.emplace_back(o.handles + a, o.handles + b);
  }
  require(o.n_bones == 0 || (o.bone != nullptr && o.bone_offsets != nullptr), "bone or bone_offsets is NULL");
  for (int64_t i = 0; i < o.n_bones; ++i) {
    const int64_t a = o.bone_offsets[i], b = o.bone_offsets[i + 1];
    require(a >= 0 && b >= a && b - a <= kMaxVertices, "bone_offsets are not ascending");
    q.bone.emplace_back(o.bone + 3 * a, o.bone + 3 * b);
  }
  LOCUS_COPY_FIELDS(q, o, exact, samples, t);
  return q;
}

}  // namespace
}  // extern "C++"

locus_status locus_skinweights_run(locus_session* session, const locus_skinweights_options* options, double* out,
                                locus_skinweights_report* out_report, const locus_run_options* opts) {
  return command_run("locus_skinweights_run", session, options, {out, "out is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    const locus::SkinningReport r = s.skinning(skinning_request_of(*options), cc.ctx);
    std::copy(r.weight.begin(), r.weight.end(), out);
    if (out_report) {
      locus_skinweights_report o;
      std::memset(&o, 0, sizeof o);
      o.exact = r.method == "exact" ? 1 : 0;
      LOCUS_COPY_FIELDS(o, r, handles, samples, sample_rings, radius, t, degenerate_vertices, factor_s, prepare_s,
                        weights_s, propagate_s);
      *out_report = o;
    }
  });
}

}  // extern "C"
