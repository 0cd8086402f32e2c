// The C API of the voronoi command (locus.h, locus_voronoi_options): the C
// options translated to the engine's request (engine/include/locus/engine/
// voronoi_request.hpp), run by the Session, the labels and report copied out.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/voronoi_request.hpp"

using namespace locus::c_api_detail;

namespace {

locus::VoronoiCommandRequest request_of(const locus_voronoi_options& o) {
  locus::VoronoiCommandRequest q;
  if (o.n_sites < 0 || o.n_sites > kMaxVertices)
    fail(ErrorCode::BadUsage, "n_sites must be in 0.." + std::to_string(kMaxVertices) + " (got " +
                                  std::to_string(o.n_sites) + ")");
  if (o.n_sites > 0) {
    require(o.sites != nullptr, "sites is NULL");
    q.sites.assign(o.sites, o.sites + o.n_sites);
  }
  LOCUS_COPY_FIELDS(q, o, random, seed, t, save, load);
  return q;
}

}  // namespace

extern "C" {

locus_voronoi_options locus_voronoi_options_default(void) {
  // t NULL: the request's "h2"
  return LOCUS_C_DEFAULTS(locus_voronoi_options, locus::VoronoiCommandRequest, random, seed);
}

locus_status locus_voronoi_run(locus_session* session, const locus_voronoi_options* options, int32_t* out_labels,
                               locus_voronoi_report* out_report, const locus_run_options* opts) {
  return command_run("locus_voronoi_run", session, options, {out_labels, "out_labels is NULL"}, opts,
                     [&](locus::Session& s, CallContext& cc) {
    const locus::VoronoiCommandReport r = s.voronoi(request_of(*options), cc.ctx);
    std::copy(r.label.begin(), r.label.end(), out_labels);
    report_into(out_report, [&](locus_voronoi_report& o) {
      o.generators = static_cast<int64_t>(r.site_xyz.size() / 3);
      o.points = static_cast<int64_t>(r.points.size() / 3);
      o.polylines = static_cast<int64_t>(r.polylines.size());
      LOCUS_COPY_FIELDS(o, r, segments, corners, empty_cells, vertices_without_heat, h, t);
    });
  });
}

}  // extern "C"
