// --save F.locus / --load F.locus of the commands that factor: the options,
// and the report's `factor_cache` object. The factoring or loading itself is
// the engine's (locus/engine/factor_store.hpp: factor_or_load, its refusals
// of a file made for another mesh, operator, t or pattern). Usage, e.g. for
// one heat operator:
//   FactorCacheOptions fc;                        // member of the command's options
//   add_factor_cache_options(app, fc);            // at registration
//   validate_factor_cache_options(fc);            // first thing in the body
//   const FactorRequest req{"heat", t, &A};
//   Factors F = factor_or_load(fc, mesh, std::span(&req, 1), ctx);
//   ... F.factors[0] ...;  j["factor_cache"] = factor_cache_json(fc, F);
#pragma once
#include <string>

#include "locus/engine/factor_store.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

using FactorCacheOptions = FactorCacheFiles;

// Adds --save and --load, bound to `save` and `load`.
void add_factor_cache_options(CLI::App* app, std::string& save, std::string& load);
inline void add_factor_cache_options(CLI::App* app, FactorCacheOptions& fc) {
  add_factor_cache_options(app, fc.save, fc.load);
}
// Error(BadUsage) for --save and --load together.
inline void validate_factor_cache_options(const FactorCacheOptions& fc) { check_factor_cache_files(fc); }

// {"loaded": FILE or null, "saved": FILE or null, "load_s", "save_s"}.
Json factor_cache_json(const FactorCacheOptions& fc, const Factors& f);
Json factor_cache_json(const FactorCacheReport& r);

}  // namespace locus::cli
