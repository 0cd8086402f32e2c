// --save / --load and the report's factor_cache object (cli_factor_cache.hpp).
#include "tools/cli/cli_factor_cache.hpp"

namespace locus::cli {

void add_factor_cache_options(CLI::App* app, std::string& save, std::string& load) {
  app->add_option("--save", save, "Save the factor(s) to FILE (.locus) after factoring")
      ->check(output_file({"locus"}));
  app->add_option("--load", load,
                  "Load the factor(s) from FILE instead of factoring; refused (exit 3) if made for another mesh, "
                  "operator or t");
}

Json factor_cache_json(const FactorCacheOptions& fc, const Factors& f) {
  return factor_cache_json(FactorCacheReport{fc.load, fc.save, f.load_s, f.save_s});
}

Json factor_cache_json(const FactorCacheReport& r) {
  Json j;
  j["loaded"] = r.loaded.empty() ? Json(nullptr) : Json(r.loaded);
  j["saved"] = r.saved.empty() ? Json(nullptr) : Json(r.saved);
  j["load_s"] = r.load_s;
  j["save_s"] = r.save_s;
  return j;
}

}  // namespace locus::cli
