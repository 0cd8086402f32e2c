// The requests and reports of the local-solve commands of thesis §4.6, as
// every front end runs them: `adf` (auto-diffusion function, one t), `hks`
// (heat kernel signature, several t) and `heat` (pairwise heat exchange):
// the CLI (`locus adf|hks|heat`), locus::Session::adf / hks / heat, the C API
// (locus_adf_options, locus_hks_options, locus_heat_options in locus.h) and
// Python (the Session methods of the same names). Each field is one option,
// named as the CLI's long option with '-' replaced by '_', with the CLI's
// default; validation, defaults and the call sequence live once, in
// engine/src/session_heat_signature_command.cpp and session_heat_command.cpp.
//
// Times are text in the grammar of heat_time.hpp: "1h2" (a multiple of h^2,
// h the mean edge length) or an absolute time ("0.001"). Each command factors
// M - t L_C for its times (one ordering and one symbolic factor for every t),
// or loads the factors from `load`, and with `save` writes them: the files
// `locus factor --matrix heat`, `voronoi` and `cvt` read and write too.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// (M - t L_C)^{-1}_ii at chosen vertices (`vertices`) or at every vertex
// (`all`): exactly one of the two. method: "subset" (an etree path per
// vertex), "selinv" (selected inversion, all vertices at once) or "full" (one
// full solve per vertex, the slow reference).
struct LOCUS_API AdfRequest {
  std::string t = "1h2";
  std::vector<int64_t> vertices;  // 0-based ids, order and repetitions kept
  bool all = false;
  std::string method = "subset";
  std::string save, load;  // factor cache files ("" = none)
};

// The same at several times `ts` (in that order).
struct LOCUS_API HksRequest {
  std::vector<std::string> ts;
  std::vector<int64_t> vertices;
  bool all = false;
  std::string method = "subset";
  std::string save, load;
};

// adf and hks: values[k * t.size() + j] is the value at the k-th evaluated
// vertex (vertices[k], or vertex k with all) for the time t[j].
struct LOCUS_API HeatSignatureReport {
  std::vector<double> values;
  std::vector<int32_t> vertices;  // the evaluated vertices; empty with all
  bool all = false;
  int32_t n = 0;                  // vertices of the mesh
  std::string method;
  double h = 0;                   // mean edge length
  std::vector<double> t;          // absolute times, in the order asked
  std::vector<std::string> t_spec;  // the times as given
  int64_t nnz_L = 0;
  int32_t supernodes = 0, etree_height = 0;
  double operator_s = 0, order_s = 0, analyze_s = 0, numeric_s = 0, query_s = 0;
  double factor_s() const { return order_s + analyze_s + numeric_s; }
  FactorCacheReport factor_cache;
  size_t count() const { return t.empty() ? 0 : values.size() / t.size(); }
};

// Unit heat at every source (repeats add), one backward-Euler step with
// M - t L_C, the heat at each target. method: "subset" (separate etree
// subtrees for the forward and the backward solve), "union" (one subtree for
// both) or "full" (full solves, the reference); repeat: run the query that
// many times (medians of the timings).
struct LOCUS_API HeatRequest {
  std::vector<int64_t> source;  // required, non-empty
  std::vector<int64_t> target;  // required, non-empty
  std::string t = "1h2";
  std::string method = "subset";
  int32_t repeat = 1;           // in 1..100000
  std::string save, load;
};

struct LOCUS_API HeatReport {
  std::vector<double> values;  // per target
  double total = 0;            // their sum
  std::vector<int32_t> sources, targets;
  std::string method;
  int32_t n = 0;
  double t = 0, h = 0;
  std::string t_spec;
  int64_t nnz_L = 0;
  int32_t etree_height = 0;
  int64_t forward_columns = 0, backward_columns = 0;  // columns of L the query visited
  int32_t repeats = 1;
  double operator_s = 0, order_s = 0, analyze_s = 0, numeric_s = 0;
  double query_s = 0, plan_s = 0, solve_s = 0;  // medians over the repeats
  double factor_s() const { return order_s + analyze_s + numeric_s; }
  FactorCacheReport factor_cache;
};

// Argument checks that need no mesh: Error(BadUsage).
LOCUS_API void check_request(const AdfRequest& req);
LOCUS_API void check_request(const HksRequest& req);
LOCUS_API void check_request(const HeatRequest& req);

}  // namespace locus
LOCUS_API_END
