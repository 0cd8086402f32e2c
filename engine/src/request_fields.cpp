// request_fields (geodesic_requests.hpp): the fields of every command's
// request with their defaults as text, what the option-parity tests hold the
// CLI, the C API and Python to. One table per command, in declaration order.
#include <string>
#include <vector>

#include "locus/engine/cvt_request.hpp"
#include "locus/engine/deform_request.hpp"
#include "locus/engine/diffusion_requests.hpp"
#include "locus/engine/factor_request.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/heat_time.hpp"
#include "locus/engine/laplacian_requests.hpp"
#include "locus/engine/nncoords_request.hpp"
#include "locus/engine/param_request.hpp"
#include "locus/engine/skinning_requests.hpp"
#include "locus/engine/voronoi_request.hpp"

namespace locus {
namespace {

const char* flag(bool b) { return b ? "true" : "false"; }

// cvt has the most options: its table apart.
std::vector<RequestField> cvt_fields() {
  const CvtRequest d;
  return {{"sites", std::to_string(d.sites)},
          {"iters", std::to_string(d.iters)},
          {"stop_energy", format_number(d.stop_energy)},
          {"anisotropy", format_number(d.anisotropy)},
          {"solver", d.solver},
          {"t", d.t},
          {"save", d.save},
          {"load", d.load},
          {"no_refine", flag(d.no_refine)},
          {"centroid_t", d.centroid_t},
          {"t_centroid", d.t_centroid},
          {"fit_rings", std::to_string(d.fit_rings)},
          {"fit_sigma", format_number(d.fit_sigma)},
          {"no_split", flag(d.no_split)},
          {"labels", d.labels},
          {"sites_out", d.sites_out},
          {"repair_rounds", std::to_string(d.repair_rounds)},
          {"refinements", std::to_string(d.refinements)},
          {"optimize", std::to_string(d.optimize)},
          {"features", format_number(d.features)},
          {"no_hausdorff", flag(d.no_hausdorff)},
          {"track_quality", flag(d.track_quality)}};
}

}  // namespace

std::vector<RequestField> request_fields(const std::string& command) {
  if (command == "geodesic") {
    const GeodesicRequest d;
    return {{"source", ""}, {"fraction", format_number(d.fraction)}, {"t", d.t}, {"t_factor", ""},
            {"save", d.save},  {"load", d.load}};
  }
  if (command == "logmap") {
    const LogmapRequest d;
    return {{"center", ""},        {"fraction", format_number(d.fraction)},
            {"t", d.t},            {"t_factor", ""},
            {"method", d.method},  {"angle", d.angle},
            {"lattice", d.lattice}, {"recenter", d.recenter},
            {"clip_injective", flag(d.clip_injective)},
            {"save", d.save},      {"load", d.load}};
  }
  if (command == "adf") {
    const AdfRequest d;
    return {{"t", d.t}, {"vertices", ""}, {"all", flag(d.all)}, {"method", d.method}, {"save", d.save},
            {"load", d.load}};
  }
  if (command == "hks") {
    const HksRequest d;
    return {{"ts", ""}, {"vertices", ""}, {"all", flag(d.all)}, {"method", d.method}, {"save", d.save},
            {"load", d.load}};
  }
  if (command == "heat") {
    const HeatRequest d;
    return {{"source", ""}, {"target", ""}, {"t", d.t}, {"method", d.method}, {"repeat", std::to_string(d.repeat)},
            {"save", d.save}, {"load", d.load}};
  }
  if (command == "deform") {
    const DeformCommandRequest d;
    return {{"roi_seed", ""},     {"roi_fraction", format_number(d.roi_fraction)},
            {"handle", ""},       {"handle_ring", std::to_string(d.handle_ring)},
            {"offset", ""},       {"energy", d.energy},
            {"regularization", format_number(d.regularization)},
            {"save", d.save},     {"load", d.load}};
  }
  if (command == "nncoords") return {{"sites", ""}, {"point", ""}, {"t", NncoordsRequest{}.t}};
  if (command == "param") {
    const ParamRequest d;
    return {{"method", d.method},   {"iters", std::to_string(d.iters)},
            {"eps", format_number(d.eps)}, {"center", std::to_string(d.center)},
            {"fraction", format_number(d.fraction)}, {"boundary", d.boundary},
            {"save", d.save},       {"load", d.load}};
  }
  if (command == "perfect-laplacian") {
    const PerfectLaplacianCommandRequest d;
    return {{"planar", flag(d.planar)},   {"iters", std::to_string(d.iters)},
            {"eps", format_number(d.eps)}, {"method", d.method},
            {"anderson", std::to_string(d.anderson)}, {"noise", format_number(d.noise)},
            {"no_active_set", flag(d.no_active_set)}};
  }
  if (command == "selfsupport") {
    const SelfSupportCommandRequest d;
    return {{"support", d.support}, {"load_density", format_number(d.load_density)},
            {"iters", std::to_string(d.iters)}, {"eps", format_number(d.eps)}};
  }
  if (command == "skinweights") {
    const SkinningRequest d;
    return {{"handles", ""}, {"bone", ""}, {"exact", flag(d.exact)}, {"samples", std::to_string(d.samples)}, {"t", d.t}};
  }
  if (command == "voronoi") {
    const VoronoiCommandRequest d;
    return {{"sites", ""}, {"random", std::to_string(d.random)}, {"t", d.t}, {"save", d.save}, {"load", d.load}};
  }
  if (command == "factor") {
    const FactorCommandRequest d;
    return {{"matrix", d.matrix}, {"t", d.t}, {"repeat", std::to_string(d.repeat)}, {"save", d.save},
            {"load", d.load}};
  }
  if (command == "cvt") return cvt_fields();
  return {};
}

}  // namespace locus
