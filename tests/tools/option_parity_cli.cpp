// Option parity of the commands whose work lives in the engine (DESIGN.md
// "Engine API": every CLI option of a command is a field of the engine's
// request for it, with the same name and default, reachable from the C API):
// the options `locus <command> --help` lists (the CLI11 app the CommandTable
// built) against the engine's request fields (request_fields), the fields of
// the C options struct in the text of locus.h, and the C defaults against the
// engine's. Python's keyword arguments: tests/python/test_option_parity.py.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "locus/engine/cvt_request.hpp"
#include "locus/engine/deform_request.hpp"
#include "locus/engine/diffusion_requests.hpp"
#include "locus/engine/factor_request.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/laplacian_requests.hpp"
#include "locus/engine/nncoords_request.hpp"
#include "locus/engine/param_request.hpp"
#include "locus/engine/skinning_requests.hpp"
#include "locus/engine/voronoi_request.hpp"
#include "locus/locus.h"
#include "tests/tools/cli_support.hpp"

namespace {

using namespace locus::test_cli;

// The commands migrated to the engine, and those still pending (their CLI
// still calls pipelines directly); together every command `locus --help` lists.
const std::vector<std::string> kMigrated = {"geodesic", "logmap",   "adf",   "hks",               "heat",
                                            "deform",   "nncoords", "param", "perfect-laplacian", "selfsupport",
                                            "voronoi",  "cvt",      "skinweights", "factor"};
const std::vector<std::string> kPending = {};
// Commands without options of their own: info (Session::info, locus_info_run,
// Python Session.info(): the report of the mesh), and run, which drives the
// other commands over a folder in child processes (tools/runner): its options
// (jobs, out, resume) are a batch front end's, not a computation's.
const std::vector<std::string> kWithoutOwnOptions = {"info"};
const std::vector<std::string> kFrontEndOnly = {"run"};

// Options of every command, the CommandTable's: threads and max_memory are
// the C API's locus_run_options (RunContext), subdivide is MeshInputOptions
// (the mesh a host passes is its own), seed is perfect-laplacian's noise seed (a
// field of its request and C options) and unused by the others;
// operator is the Session's construction option (SessionOptions, locus_session_create_ex; factor's
// --operator is the older spelling of its --matrix, whose field is matrix), no_weld
// the reader's (ReadOptions); json, output, preview, preview_t and view are the CLI's presentation of a result.
const std::set<std::string> kCommon = {"help", "json", "output", "threads", "seed", "subdivide", "max_memory",
                                       "preview", "preview_t", "view", "operator", "no_weld"};

std::string field_name(std::string option) {
  std::replace(option.begin(), option.end(), '-', '_');
  return option;
}

// The long options of `locus <command> --help`, in order, the first spelling
// of each (--recenter, not its alias --recentre), '-' as '_'.
std::vector<std::string> cli_options(const std::string& command) {
  Scratch dir("parity");
  const Run r = run_locus(dir, {command, "--help"});
  REQUIRE(r.status == 0);
  std::vector<std::string> out;
  std::istringstream in(r.out);
  std::string line;
  const std::regex option(R"(^\s+(?:-[A-Za-z],)?--([a-z][a-z0-9-]*))");
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, option)) out.push_back(field_name(m[1]));
  return out;
}

// The fields of `typedef struct NAME { ... } NAME;` in locus.h (or locus_commands.h, which it includes).
std::vector<std::string> c_struct_fields(const std::string& name) {
  std::stringstream ss;  // locus.h and the header of the commands it includes
  for (const char* h : {"/locus.h", "/locus_commands.h"}) {
    std::ifstream f(std::string(LOCUS_TEST_DATA_DIR "/../../engine/include/locus") + h);
    ss << f.rdbuf();
  }
  const std::string text = ss.str();
  const size_t at = text.find("typedef struct " + name + " {");
  REQUIRE(at != std::string::npos);
  const size_t end = text.find("} " + name + ";", at);
  std::string body = text.substr(at, end - at);
  body = std::regex_replace(body, std::regex(R"(/\*[\s\S]*?\*/)"), "");
  std::vector<std::string> out;
  const std::regex decl(R"(([A-Za-z_][A-Za-z0-9_]*)\s*(?:\[[0-9]*\])?\s*;)");  // offset[3]; too
  for (auto it = std::sregex_iterator(body.begin(), body.end(), decl); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

std::vector<std::string> engine_fields(const std::string& command) {
  std::vector<std::string> out;
  for (const locus::RequestField& f : locus::request_fields(command)) out.push_back(f.name);
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

TEST_CASE("option parity: every command is migrated or listed as pending") {
  if (!have_locus()) return;
  Scratch dir("parity-list");
  const Run r = run_locus(dir, {"--help"});
  REQUIRE(r.status == 0);
  const std::regex command(R"(^\s+([a-z][a-z-]*)\s{2,})");
  std::istringstream in(r.out);
  std::string line;
  bool in_commands = false;
  std::smatch m;
  int seen = 0;
  while (std::getline(in, line)) {
    if (line.rfind("Subcommands:", 0) == 0) in_commands = true;
    if (!in_commands || !std::regex_search(line, m, command)) continue;
    ++seen;
    CHECK_MESSAGE((contains(kMigrated, m[1]) || contains(kPending, m[1]) || contains(kWithoutOwnOptions, m[1]) ||
                   contains(kFrontEndOnly, m[1])),
                  "command " << m[1]);
  }
  CHECK(seen == static_cast<int>(kMigrated.size() + kPending.size() + kWithoutOwnOptions.size() +
                                 kFrontEndOnly.size()));
}

TEST_CASE("option parity: a command without options of its own has only the common ones") {
  if (!have_locus()) return;
  for (const std::string& command : kWithoutOwnOptions) {
    CAPTURE(command);
    for (const std::string& o : cli_options(command)) {
      CAPTURE(o);
      CHECK(kCommon.count(o) == 1);
    }
    CHECK(engine_fields(command).empty());
  }
}

TEST_CASE("option parity: each CLI option of a migrated command is an engine field and a C field") {
  if (!have_locus()) return;
  for (const std::string& command : kMigrated) {
    CAPTURE(command);
    const std::vector<std::string> cli = cli_options(command);
    const std::vector<std::string> engine = engine_fields(command);
    const std::vector<std::string> c = c_struct_fields("locus_" + field_name(command) + "_options");
    REQUIRE(!engine.empty());
    for (const std::string& o : cli) {
      if (kCommon.count(o)) continue;
      CAPTURE(o);
      CHECK(contains(engine, o));
    }
    // And the other way: no engine field the CLI cannot set, none missing in C.
    for (const std::string& f : engine) {
      CAPTURE(f);
      CHECK(contains(cli, f));
      CHECK(contains(c, f));
    }
  }
}

TEST_CASE("option parity: the C options' defaults are the engine's") {
  const locus_geodesic_options g = locus_geodesic_options_default();
  const locus::GeodesicRequest gq;
  CHECK(g.source == gq.source);
  CHECK(g.fraction == gq.fraction);
  CHECK(g.t == nullptr);
  CHECK(g.t_factor == 0.0);
  CHECK(g.save == nullptr);
  CHECK(g.load == nullptr);
  const locus_logmap_options l = locus_logmap_options_default();
  const locus::LogmapRequest lq;
  CHECK(l.center == lq.center);
  CHECK(l.fraction == lq.fraction);
  CHECK((l.clip_injective != 0) == lq.clip_injective);
  // NULL strings mean the engine's defaults, which request_fields lists.
  CHECK(l.method == nullptr);
  CHECK(l.angle == nullptr);
  CHECK(l.lattice == nullptr);
  CHECK(l.recenter == nullptr);
  const locus_adf_options a = locus_adf_options_default();
  const locus::AdfRequest aq;
  CHECK((a.all != 0) == aq.all);
  CHECK(a.t == nullptr);  // NULL: the request's "1h2"
  CHECK(a.method == nullptr);
  CHECK(a.n_vertices == 0);
  const locus_hks_options k = locus_hks_options_default();
  CHECK((k.all != 0) == locus::HksRequest{}.all);
  CHECK(k.n_ts == 0);
  const locus_heat_options h = locus_heat_options_default();
  const locus::HeatRequest hq;
  CHECK(h.repeat == hq.repeat);
  CHECK(h.t == nullptr);
  CHECK(h.method == nullptr);
  for (const locus::RequestField& f : locus::request_fields("adf")) {
    if (f.name == "t") CHECK(f.default_value == "1h2");
    if (f.name == "method") CHECK(f.default_value == "subset");
  }
  const locus_deform_options d = locus_deform_options_default();
  const locus::DeformCommandRequest dq;
  CHECK(d.roi_seed == dq.roi_seed);
  CHECK(d.roi_fraction == dq.roi_fraction);
  CHECK(d.handle == dq.handle);
  CHECK(d.handle_ring == dq.handle_ring);
  CHECK(d.regularization == dq.regularization);
  CHECK(d.energy == nullptr);  // NULL: the request's "laplacian"
  const locus_nncoords_options n = locus_nncoords_options_default();
  CHECK(n.t == nullptr);  // NULL: the request's "h2"
  CHECK(n.n_sites == 0);
  CHECK(n.point.face == locus::NncoordsRequest{}.point.face);
  const locus_param_options p = locus_param_options_default();
  const locus::ParamRequest pq;
  CHECK(p.iters == pq.iters);
  CHECK(p.eps == pq.eps);
  CHECK(p.center == pq.center);
  CHECK(p.fraction == pq.fraction);
  CHECK(p.method == nullptr);
  CHECK(p.boundary == nullptr);
  const locus_perfect_laplacian_options pl = locus_perfect_laplacian_options_default();
  const locus::PerfectLaplacianCommandRequest plq;
  CHECK((pl.planar != 0) == plq.planar);
  CHECK(pl.iters == plq.iters);
  CHECK(pl.eps == plq.eps);
  CHECK(pl.anderson == plq.anderson);
  CHECK((pl.no_active_set != 0) == plq.no_active_set);
  CHECK(pl.noise == plq.noise);
  CHECK(pl.seed == plq.seed);
  CHECK(pl.method == nullptr);
  const locus_selfsupport_options ss = locus_selfsupport_options_default();
  const locus::SelfSupportCommandRequest ssq;
  CHECK(ss.load_density == ssq.load_density);
  CHECK(ss.iters == ssq.iters);
  CHECK(ss.eps == ssq.eps);
  CHECK(ss.support == nullptr);
  const locus_voronoi_options vo = locus_voronoi_options_default();
  const locus::VoronoiCommandRequest vq;
  CHECK(vo.random == vq.random);
  CHECK(vo.seed == vq.seed);
  CHECK(vo.t == nullptr);  // NULL: the request's "h2"
  CHECK(vo.n_sites == 0);
  const locus_cvt_options cv = locus_cvt_options_default();
  const locus::CvtRequest cq;
  CHECK(cv.sites == cq.sites);
  CHECK(cv.iters == cq.iters);
  CHECK(cv.stop_energy == cq.stop_energy);
  CHECK(cv.anisotropy == cq.anisotropy);
  CHECK((cv.no_refine != 0) == cq.no_refine);
  CHECK(cv.fit_rings == cq.fit_rings);
  CHECK(cv.fit_sigma == cq.fit_sigma);
  CHECK((cv.no_split != 0) == cq.no_split);
  CHECK(cv.repair_rounds == cq.repair_rounds);
  CHECK(cv.refinements == cq.refinements);
  CHECK(cv.optimize == cq.optimize);
  CHECK(cv.features == cq.features);
  CHECK((cv.no_hausdorff != 0) == cq.no_hausdorff);
  CHECK((cv.track_quality != 0) == cq.track_quality);
  CHECK(cv.seed == cq.seed);
  CHECK(cv.solver == nullptr);  // NULL: the request's "local"
  CHECK(cv.t == nullptr);       // NULL: the request's "4h2"
  CHECK(cv.centroid_t == nullptr);
  CHECK(cv.t_centroid == nullptr);
  CHECK(cv.labels == nullptr);
  CHECK(cv.sites_out == nullptr);
  const locus_skinweights_options sw = locus_skinweights_options_default();
  const locus::SkinningRequest sq;
  CHECK((sw.exact != 0) == sq.exact);
  CHECK(sw.samples == sq.samples);
  CHECK(sw.t == nullptr);  // NULL: the request's "" (h^2)
  CHECK(sw.n_handles == 0);
  CHECK(sw.n_bones == 0);
  const locus_factor_options fa = locus_factor_options_default();
  const locus::FactorCommandRequest fq;
  CHECK(fa.repeat == fq.repeat);
  CHECK(fa.seed == fq.seed);
  CHECK(fa.matrix == nullptr);  // NULL: the request's "heat"
  CHECK(fa.t == nullptr);       // NULL: the request's "" (h^2)
  CHECK(fa.save == nullptr);
  CHECK(fa.load == nullptr);
  for (const locus::RequestField& f : locus::request_fields("factor")) {
    if (f.name == "matrix") CHECK(f.default_value == "heat");
    if (f.name == "repeat") CHECK(f.default_value == "1");
  }
  for (const locus::RequestField& f : locus::request_fields("cvt")) {
    if (f.name == "t") CHECK(f.default_value == "4h2");
    if (f.name == "solver") CHECK(f.default_value == "local");
    if (f.name == "fit_sigma") CHECK(f.default_value == "1");
    if (f.name == "features") CHECK(f.default_value == "0");
  }
  for (const locus::RequestField& f : locus::request_fields("heat"))
    if (f.name == "repeat") CHECK(f.default_value == "1");
  for (const locus::RequestField& f : locus::request_fields("logmap")) {
    if (f.name == "method") CHECK(f.default_value == lq.method);
    if (f.name == "fraction") CHECK(f.default_value == "0.05");
    if (f.name == "clip_injective") CHECK(f.default_value == "false");
  }
}
