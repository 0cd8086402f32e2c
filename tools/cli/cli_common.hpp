// The shared grammar of the `locus` and `locus-bench` tools (DESIGN.md "The
// command-line contract"): `tool <command> <mesh-file> [options]` with the
// common options --json, -o/--output, --threads, --seed, --subdivide; exit
// status 0 ok, 2 bad usage, 3 bad input, 4 numerical failure, 5 cancelled.
//
// A command is a name, a description, its own options and a body. The
// CommandTable owns parsing, the thread budget (tbb::global_control), the
// SIGINT cancel flag and the mapping from exceptions to exit statuses, so a new
// command only declares its options and writes its body: load the input with
// load_input(), compute, emit() a JSON object.
#pragma once
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/sparse_matrix.hpp"

namespace locus::cli {

// JSON objects keep their keys in insertion order, so outputs read top-down
// (command, input, sizes, timings, quality) rather than alphabetically.
using Json = nlohmann::ordered_json;

// Options every command accepts, with the contract's defaults.
struct CommonOptions {
  std::string mesh_path;  // positional <mesh-file>
  bool json = false;      // one JSON object on stdout, logs on stderr
  std::string output;     // -o FILE: result file, format from the extension ("" = none)
  int threads = 0;        // 0 = all cores
  uint64_t seed = 1;      // every random choice derives from it
  int subdivide = 0;      // 1:4 midpoint subdivisions after loading
  std::string max_memory; // --max-memory SIZE as given ("" = default: 80% of physical memory)
};

// A command's body runs after a successful parse and returns the exit status
// (normally 0); failures are thrown as locus::Error and mapped by the table.
using CommandBody = std::function<int(const CommonOptions&, const RunContext&)>;

class CommandTable {
 public:
  // `tool_name` prefixes every message ("locus: error: ...").
  CommandTable(std::string tool_name, std::string description);
  ~CommandTable();
  CommandTable(const CommandTable&) = delete;
  CommandTable& operator=(const CommandTable&) = delete;

  // Declares `<tool> <name> <mesh-file> [common options]`; the caller adds the
  // command's own options to the returned app (owned by the table).
  CLI::App* add(const std::string& name, const std::string& description, CommandBody body);

  // Lists a command with its own grammar in --help without parsing it (the caller dispatches it).
  void add_listing(const std::string& name, const std::string& description);

  // Names of the commands added with add(), in order.
  std::vector<std::string> names() const;

  // Parses argv, runs the chosen command and returns the exit status. Never throws.
  int run(int argc, char** argv);

 private:
  struct Command;
  std::string tool_;
  CLI::App app_;
  std::vector<std::unique_ptr<Command>> commands_;
};

// Monotonic stopwatch for phase timings, in seconds.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

// The mesh a command works on: read from <mesh-file>, polygons triangulated
// (triangle-only commands, issue 22 item 6), then subdivided.
struct Input {
  Mesh mesh;
  MeshAttributes attributes;  // the file's vertex attributes (PLY), carried to outputs on its vertices
  double load_s = 0;       // reading and parsing the file
  double triangulate_s = 0;  // polygons into triangles (0 when not needed)
  double subdivide_s = 0;  // --subdivide (0 when not asked)
  // When the file's polygons were triangulated: the file's faces on the same
  // vertices, and per triangle of `mesh` the file's face it belongs to.
  Mesh polygons;
  std::vector<int32_t> face_of;
  bool triangulated() const { return !face_of.empty(); }
};

// What load_input does with faces of more than 3 corners: triangulate them
// (ear clipping, kernels/mesh/polygon_triangulation.hpp) for the commands that
// need triangles, or keep them for those that take polygons (info, the
// chapter-2 commands). A later per-command native polygon path only passes Keep.
enum class PolygonFaces { Triangulate, Keep };

// Reads the mesh (locus::read_mesh), triangulates polygons (Triangulate) and
// applies --subdivide. Throws Error(BadInput) for unreadable files, polygons
// that cannot be triangulated (naming the face), for subdividing a polygon
// mesh (Keep) and when the subdivision would overflow 32-bit face indices, and
// Error(ResourceLimit) when it would exceed the memory limit (subdivision_budget.hpp).
Input load_input(const CommonOptions& opt, const RunContext& ctx, PolygonFaces faces = PolygonFaces::Triangulate);

// The mesh an output on the input's vertices is written with: the file's
// polygons when they were triangulated (the vertices are the same), else the
// mesh the command worked on. With new positions (deform) use with_positions.
const Mesh& output_faces(const Input& in);
Mesh with_positions(const Input& in, const Mesh& moved);
// A point given on the file's faces (FACE, weights of its corners 0, 1, 2) as
// a point of the mesh the command works on: unchanged for a triangle file;
// for a triangulated polygon the triangle of that polygon holding the point.
// Error(BadInput) naming `what` when the face does not exist or the point is
// outside the polygon (both depend on the file).
SurfacePoint point_on_file_face(const Input& in, const SurfacePoint& p, const std::string& what);

// The worker threads a command runs with: --threads N, or all cores for 0
// (what the JSON key `threads` reports).
int threads_used(const CommonOptions& opt);

// {"file", "subdivide", "n_vertices", "n_faces"} of the loaded input, and for
// a triangulated file "triangulated": {"polygons": faces in the file, "triangles"}.
Json input_json(const CommonOptions& opt, const Input& in);

// Up-front checks of -o for commands whose result a format cannot hold
// (Error(BadUsage) naming the alternative, before the input is read):
// results with texture coordinates refuse .off; commands whose result is only
// the JSON refuse -o altogether.
void check_uv_output(const CommonOptions& opt, const std::string& command);
void refuse_output(const CommonOptions& opt, const std::string& command, const std::string& result);

// Write options for an output on the input's vertices (issue 22 item 2): the
// input file's vertex attributes with their types, float positions kept as
// float. Normals are dropped when the command moved the vertices; u/v when
// the result has UVs of its own (they replace them).
WriteOptions carried_attributes(const Input& in, bool positions_changed = false, bool result_uv = false);
// Adds a result property, replacing an input attribute of the same name.
void add_result(WriteOptions& wo, VertexProperty p);

// Writes `m` to -o FILE when one was given (format from the extension).
void write_output_mesh(const CommonOptions& opt, const Mesh& m, const WriteOptions& wo = {});

// With --json prints `result` as one JSON object on stdout; otherwise calls
// `human` with stdout.
void emit(const CommonOptions& opt, const Json& result, const std::function<void(std::ostream&)>& human);

// A log line on stderr ("<tool>: <text>"); stdout stays reserved for results.
void log(const std::string& text);

// Diffusion time: an absolute value ("0.001", "1e-3") or a multiple of h^2,
// h = mean edge length ("h2", "2h2", "500h2"), as geometry-central's tCoef.
struct TimeSpec {
  double value = 1.0;
  bool times_h2 = true;  // value is a multiple of h^2
  double resolve(double h) const { return times_h2 ? value * h * h : value; }
};
// Throws Error(BadUsage) naming the text unless it is a finite positive time.
TimeSpec parse_time_spec(const std::string& text);

// The one heat-time grammar of every command (issue 22 item 8): --t T, T as
// parse_time_spec reads it. The heat-method commands (geodesic, logmap) also
// accept their older --t-factor C, meaning --t Ch2, as a deprecated alias
// (a note on stderr). Usage:
//   HeatTimeOptions ht;                                   // member of the command's options
//   add_heat_time_options(app, ht, "h2", true);           // at registration
//   const TimeSpec ts = heat_time_spec(ht, {1.0, true});  // before reading the input
//   ... t_factor = heat_t_factor(ts, mean_edge_length(mesh)) ...
struct HeatTimeOptions {
  std::string t_text;   // --t ("" = the command's default)
  std::string t_factor;  // --t-factor C as given ("" = not given)
};
void add_heat_time_options(CLI::App* app, HeatTimeOptions& ht, const std::string& default_text, bool factor_alias);
// A deprecated spelling's bare number C (a multiple of h^2): Error(BadUsage)
// naming `option` unless it is finite and > 0 (>= 0 with allow_zero).
double parse_h2_multiple(const std::string& text, const std::string& option, bool allow_zero);
// Error(BadUsage) for both spellings at once, a bad --t or a non-positive --t-factor.
TimeSpec heat_time_spec(const HeatTimeOptions& ht, const TimeSpec& default_spec);
// The JSON's `t_spec`: --t as given, else the time used as a multiple of h^2 ("4h2").
std::string heat_time_text(const HeatTimeOptions& ht, double t_factor);
// The spec as a multiple of h^2 on a mesh of mean edge length h (the heat method's t_factor).
double heat_t_factor(const TimeSpec& ts, double h);

// The operators the tools factor (--operator heat|laplacian, --t T).
struct OperatorSpec {
  std::string kind = "heat";  // "heat": M - t L_C;  "laplacian": -L_C + eps M
  std::string t_text;         // --t as given ("" = default h^2)
};
struct BuiltOperator {
  CscMatrix A;
  double t = 0;  // diffusion time used (0 for the Laplacian)
  double h = 0;  // mean edge length of the mesh
};
// Rejects an empty option value: `--t ''` would otherwise read as "not given"
// and silently fall back to the default.
inline CLI::Validator non_empty() {
  return CLI::Validator([](std::string& v) { return v.empty() ? std::string("must not be empty") : std::string(); },
                        "NONEMPTY");
}
// Adds --operator and --t to a command.
void add_operator_options(CLI::App* app, OperatorSpec& spec);
// Checks the spec before any work (BadUsage: --t with the Laplacian, bad --t).
void validate_operator_spec(const OperatorSpec& spec);
// Checks the mesh suits the operators (triangles, manifold, no degenerate
// faces, no unreferenced vertices; BadInput otherwise) and builds A.
BuiltOperator build_operator(const Mesh& m, const OperatorSpec& spec);

// --max-memory SIZE: bytes, or a number with a K, M, G or T suffix (powers of
// 1024; "512M", "1.5G", "2GiB" and "2GB" are the same as their binary forms).
// Throws Error(BadUsage) naming the text otherwise. The CommandTable parses it
// before the body runs and puts it in RunContext::max_memory_bytes.
std::size_t parse_memory_size(const std::string& text);

// ---- Factor cache (--save F.locus / --load F.locus, io/include/locus/io/factor_cache.hpp) ----
//
// A command that factors declares the options with add_factor_cache_options,
// checks them with validate_factor_cache_options before reading the mesh, and
// gets its factors from factor_or_load, which either
//  * loads them from --load F (refusing, with Error(BadInput) = exit 3, a file
//    made for another mesh (content hash after --subdivide), for other
//    operators or another t, for another matrix pattern, of another format
//    version, truncated or corrupted), or
//  * orders, analyzes and factors every requested operator (one ordering and
//    one symbolic factor, from the first matrix: all must share its pattern)
//    and, with --save F, writes them.
// Usage, e.g. for one heat operator:
//   FactorCacheOptions fc;                        // member of the command's options
//   add_factor_cache_options(app, fc);            // at registration
//   validate_factor_cache_options(fc);            // first thing in the body
//   const CscMatrix A = heat_operator(mesh, t);
//   const FactorRequest req{"heat", t, &A};
//   Factors F = factor_or_load(fc, mesh, std::span(&req, 1), ctx);
//   ... F.factors[0] ...;  j["factor_cache"] = factor_cache_json(fc, F);
struct FactorCacheOptions {
  std::string save;  // --save FILE ("" = none)
  std::string load;  // --load FILE ("" = factor)
};
void add_factor_cache_options(CLI::App* app, FactorCacheOptions& fc);
// Error(BadUsage) for --save and --load together.
void validate_factor_cache_options(const FactorCacheOptions& fc);

// One operator to factor: its label (kind, t) is stored in the file and must
// match on load; t is compared with a relative tolerance of 1e-12.
struct FactorRequest {
  std::string kind;             // "heat", "laplacian", "poisson", "deform-bilaplacian", ...
  double t = 0;                 // 0 when the operator has no time (or another scalar parameter, e.g. eps)
  const CscMatrix* A = nullptr; // lower CSC, original vertex numbering
};
struct Factors {
  std::shared_ptr<const SymbolicFactor> symbolic;
  std::vector<NumericFactor> factors;  // one per request, in order
  bool loaded = false;
  double order_s = 0, analyze_s = 0, numeric_s = 0;  // 0 when loaded
  double load_s = 0, save_s = 0;
  double factor_s() const { return order_s + analyze_s + numeric_s; }
};
Factors factor_or_load(const FactorCacheOptions& fc, const Mesh& m, std::span<const FactorRequest> ops,
                       const RunContext& ctx);
// {"loaded": FILE or null, "saved": FILE or null, "load_s", "save_s"}.
Json factor_cache_json(const FactorCacheOptions& fc, const Factors& f);

// ---- Previews (--preview out.png [--view x,y,z], kernels/include/locus/kernels/render/rasterize.hpp, io/include/locus/io/write_png.hpp) ----
//
// A shaded picture of the mesh coloured by a per-vertex result, seen from its
// principal axes (preview_camera.hpp) or from --view, with a legend strip
// (the quantity, its range or labels, the marker) and markers at sources,
// centres or sites; 800 x 800. Usage:
//   PreviewOptions preview;                         // member of the command's options
//   add_preview_option(app, preview);               // at registration: --preview and --view
//   check_preview_options(preview);                 // before reading the mesh (BadUsage unless "" or *.png, bad --view)
//   write_preview(mesh, values, PreviewKind::Scalar, preview, {"distance from vertex 3", {p}, "source"});
//                                                   // after computing; no-op when preview.path == ""
enum class PreviewKind {
  Scalar,   // values: nv numbers (distance, adf, ...), colour map from min to max with iso-bands; NaN = no value (grey)
  Labels,   // values: nv integer labels (cvt cells), one distinct colour per label, negative = grey
  Checker,  // values: 2 nv numbers, (u, v) per vertex interleaved; a checkerboard of the UVs, NaN = grey
};
struct PreviewOptions {
  std::string path;  // --preview FILE.png ("" = none)
  std::string view;  // --view x,y,z: the camera's side ("" = from the principal axes)
};
struct PreviewContent {
  std::string title;                        // the quantity (legend)
  std::vector<std::array<double, 3>> markers;  // sources, centres, sites
  std::string marker_label;                 // what the markers are ("source", "sites")
  bool edges = false;                       // draw the triangle edges (remesh)
  double clip = 0;                          // Scalar: colours span the clip..1-clip quantiles (rasterize.hpp)
};
// A CLI11 check for options naming a file the command writes: the extension
// is one of `extensions` (lower case, no dot) and io::check_output_path()
// accepts the path (folder exists and is writable; the target is absent or a
// regular file). It runs at parse time, so a bad output path is exit 2 before
// any input is read.
CLI::Validator output_file(std::vector<std::string> extensions);
void add_preview_option(CLI::App* app, PreviewOptions& preview);
void check_preview_path(const std::string& path);
// check_preview_path and --view's grammar (three numbers, not all zero).
void check_preview_options(const PreviewOptions& preview);
// `FILE.png` with `suffix` before the extension ("x.png", "-t0" -> "x-t0.png"):
// the names of several images from one --preview (hks: one per t).
std::string preview_path_with(const std::string& path, const std::string& suffix);
// Renders and writes the PNG to `path` (default preview.path) (Error(BadUsage)
// if values has the wrong size, Error(BadInput) if the file cannot be
// written); logs "wrote <path>" once the command succeeded (written_files.hpp).
void write_preview(const Mesh& m, std::span<const double> values, PreviewKind kind, const PreviewOptions& preview,
                   const PreviewContent& content, const std::string& path = "");

// A number for messages: %.6g ("1e+12", "0.000134", "nan"), not std::to_string's fixed notation.
std::string format_number(double v);

// Median of a non-empty sample (mean of the two middle values for even sizes).
double median(std::vector<double> v);

// n deterministic pseudo-random values in [-1, 1) from `seed` (splitmix64), the
// same on every platform, unlike std::uniform_real_distribution.
std::vector<double> random_vector(size_t n, uint64_t seed);

// ||A x - b|| / ||b|| for a lower-stored symmetric A.
double relative_residual(const CscMatrix& A, const double* x, const double* b);

// Commands of the `locus` tool, one file each (tools/cli/cmd_<name>.cpp).
void register_info_command(CommandTable& table);
void register_perfect_laplacian_commands(CommandTable& table);  // perfect-laplacian, param, selfsupport
void register_factor_command(CommandTable& table);
void register_deform_command(CommandTable& table);
void register_local_solve_commands(CommandTable& table);  // adf, hks, heat
void register_voronoi_command(CommandTable& table);
void register_cvt_command(CommandTable& table);
void register_geodesic_commands(CommandTable& table);  // geodesic, logmap

}  // namespace locus::cli
