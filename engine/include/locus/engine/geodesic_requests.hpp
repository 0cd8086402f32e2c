// The requests and reports of the heat-method commands, `geodesic` and
// `logmap` (thesis §6.4-6.6), as every front end runs them: the CLI
// (`locus geodesic`, `locus logmap`), locus::Session::geodesic / logmap, the C
// API (locus_geodesic_options, locus_logmap_options in locus.h) and Python
// (locus.geodesic, locus.logmap and the Session methods). Each field is one
// option, named as the CLI's long option with '-' replaced by '_', with the
// CLI's default; validation, defaults and the call sequence live once, in
// engine/src/session_geodesic_command.cpp and session_logmap_command.cpp.
//
// Diffusion time (both): `t` as text ("" = the default, 4h2 on triangle
// meshes, 8h2 on polygon meshes; "Ch2" a multiple of h^2, h the mean edge
// length; or an absolute time in length^2), or `t_factor` = C meaning "Ch2"
// (the older spelling; not both). A query costs the same at any t.
// Factor cache (both): `save` / `load` a file of the heat method's two
// factors (engine/include/locus/engine/factor_store.hpp); a polygon mesh then
// runs on its triangulation.
#pragma once
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// Where a factor cache file was read or written, and how long that took.
struct LOCUS_API FactorCacheReport {
  std::string loaded, saved;  // "" = none
  double load_s = 0, save_s = 0;
  bool used() const { return !loaded.empty() || !saved.empty(); }
};

// Heat geodesic distance from one vertex: on the whole mesh (fraction 1, full
// solves) or localized to the geodesic disk of round(fraction * nv) vertices
// around the source (exact subset solves, thesis §6.4.2).
struct LOCUS_API GeodesicRequest {
  int64_t source = -1;                  // source vertex, 0-based (required)
  double fraction = 1.0;                // in (0, 1]
  std::string t;                        // diffusion time (above); "" = default
  std::optional<double> t_factor;       // t = t_factor h^2 (above); empty = not given
  std::string save, load;               // factor cache files ("" = none)
};

struct LOCUS_API GeodesicReport {
  std::vector<double> distance;  // per vertex, units of the positions; NaN = no value (outside the patch, unreachable)
  std::vector<double> valid;     // per vertex: 1 where distance has a value, else 0
  int32_t source = -1;
  std::string method;            // "heat-full", "heat-local" or "heat-full-polygon"
  double fraction = 1.0;
  double t_factor = 0, t = 0, h = 0;  // the time used: t = t_factor h^2
  std::string t_spec;                 // the time as given, else "<t_factor>h2"
  int32_t patch_size = 0;             // vertices computed (all for the whole mesh)
  double max_distance = 0;
  int64_t unreachable = 0;            // vertices in other connected components than the source
  int64_t heat_underflow_vertices = 0;  // the heat underflowed there (no direction: distance interpolated)
  double t_avoiding_underflow = 0;      // a t that avoids it (0 when none underflowed)
  std::vector<std::string> warnings;
  double precompute_s = 0, patch_s = 0, query_s = 0;
  FactorCacheReport factor_cache;
  // With the operator `auto` on a clean mesh, the cotan heat method can still
  // fail where badly shaped triangles make its distance negative; the query is
  // then answered on the robust operator and this says why ("" otherwise).
  std::string operator_fallback;
};

// Log map (geodesic polar coordinates) of the geodesic disk of
// round(fraction * nv) vertices around `center` (thesis §6.5-6.6).
struct LOCUS_API LogmapRequest {
  int64_t center = -1;              // center vertex, 0-based (required)
  double fraction = 0.05;           // in (0, 1]
  std::string t;                    // diffusion time (above); "" = default
  std::optional<double> t_factor;   // t = t_factor h^2; empty = not given
  std::string method = "heat";      // heat (localized), heat-full (full solves) or dem (Dijkstra-based baseline)
  std::string angle = "auto";       // heat map's angle estimator: auto, log, two-ring or average
  std::string lattice = "default";  // lattice correction: default (the library's, path), none, star, ring or path
  std::string recenter = "default";  // recenter the gradients: default (the library's, on), on or off
  bool clip_injective = false;      // keep only the patch vertices closer than the injectivity radius
  std::string save, load;           // factor cache files ("" = none)
};

struct LOCUS_API LogmapReport {
  // The patch (center first) and per patch vertex: heat geodesic distance,
  // polar angle and Cartesian coordinates (u, v) = distance (cos, sin)(angle).
  std::vector<int32_t> patch;
  std::vector<double> distance, angle, u, v;
  int32_t center = -1;
  std::string method;                 // as asked, or "heat-full-polygon" on a polygon mesh
  std::string angle_estimator;        // as asked; "dem" for the DEM, "log" on polygons
  double fraction = 0.05;
  double t_factor = 0, t = 0, h = 0;  // t, h: the heat methods only
  std::string t_spec;
  bool heat = false;                  // a heat method ran (the statistics below apply)
  bool polygon = false;               // the polygon log map ran (flipped counts polygons)
  int32_t sources = 0, batches = 0, passes = 0, angle_fallbacks = 0;
  bool two_ring = false, recentered = false;
  int64_t heat_underflow_vertices = 0;
  double t_avoiding_underflow = 0;
  std::vector<std::string> warnings;
  double max_distance = 0;
  int64_t flipped = 0;  // flipped triangles (polygons on a polygon mesh) of the map
  // The largest radius with no flipped triangle; +infinity when none flipped.
  double injectivity_radius = std::numeric_limits<double>::infinity();
  int32_t clipped_vertices = 0;  // clip_injective: patch vertices dropped
  double precompute_s = 0, patch_s = 0, query_s = 0;
  FactorCacheReport factor_cache;
};

// Argument checks that need no mesh (ranges, the time's grammar, names of
// methods, save and load together): Error(BadUsage). The Session runs them
// on every request; the CLI also before reading the file.
LOCUS_API void check_request(const GeodesicRequest& req);
LOCUS_API void check_request(const LogmapRequest& req);

// The faces a command reads a polygon file with (MeshInputOptions): the
// heat method runs on the polygons themselves (Keep) unless the request needs
// triangles (a localized geodesic, the DEM, a factor cache).
LOCUS_API bool keeps_polygons(const GeodesicRequest& req);
LOCUS_API bool keeps_polygons(const LogmapRequest& req);

// The fields of a command's request, in declaration order, with their
// defaults as text ("" = none or not given; booleans "false"/"true"): what
// the option-parity tests hold the CLI, the C API and Python to. Commands:
// "geodesic", "logmap"; empty for another name.
struct LOCUS_API RequestField {
  std::string name;
  std::string default_value;
};
LOCUS_API std::vector<RequestField> request_fields(const std::string& command);

}  // namespace locus
LOCUS_API_END
