// The input and the output files of a command: the mesh read from
// <mesh-file> by the engine (locus/engine/mesh_input.hpp: polygons
// triangulated or kept, --subdivide), and what an output on its vertices is
// written with (the file's faces and vertex attributes, -o's format checks).
#pragma once
#include <string>

#include "locus/engine/mesh_input.hpp"
#include "locus/session.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"
#include "tools/cli/cli_report.hpp"

namespace locus::cli {

// The mesh a command works on (engine/include/locus/engine/mesh_input.hpp).
using Input = MeshInput;

// Reads <mesh-file> with --subdivide (load_mesh_input) and records its load
// and subdivision times for the report's timings.
Input load_input(const CommonOptions& opt, const RunContext& ctx, PolygonFaces faces = PolygonFaces::Triangulate);
// The same, leaving the operator's choice to the Session made from it
// (MeshInputOptions::choose_operator false): one edge incidence and report
// instead of two. Once the Session exists, take_session_operator fills in.op.
Input load_input_for_session(const CommonOptions& opt, const RunContext& ctx);
void take_session_operator(Input& in, const Session& session, const RunContext& ctx);

// The mesh an output on the input's vertices is written with: the file's
// polygons when they were triangulated (the vertices are the same), else the
// mesh the command worked on. With new positions (deform) use with_positions.
inline const Mesh& output_faces(const Input& in) { return in.output_faces(); }
Mesh with_positions(const Input& in, const Mesh& moved);
// A point given on the file's faces (FACE, weights of its corners 0, 1, 2) as
// a point of the mesh the command works on: unchanged for a triangle file;
// for a triangulated polygon the triangle of that polygon holding the point.
// Error(BadUsage) naming `what` when the face does not exist or the point is
// outside the polygon.
SurfacePoint point_on_file_face(const Input& in, const SurfacePoint& p, const std::string& what);
// A vertex id given on the command line that the file does not have: an error
// that depends on the file, Error(BadInput) = exit 3 (README "Exit status").
// Negative ids are left to the engine's checks (bad usage whatever the file).
void check_file_vertex(const std::string& option, int64_t v, const Input& in, const CommonOptions& opt);

// {"file", "subdivide", "n_vertices", "n_faces"} of the loaded input, and for
// a triangulated file "triangulated": {"polygons": faces in the file, "triangles"};
// "operator" (operator_json) when the robust operator is used or --operator was
// given; "weld" (weld_json) for an asset file read through assimp.
Json input_json(const CommonOptions& opt, const Input& in);
// {"used": cotan|robust, "asked", "reason", "defects": {counts per kind}}.
Json operator_json(const OperatorReport& op);
// How an asset file's vertices became the mesh's: counts, and file_to_vertex
// (file vertex -> result vertex) so results can be mapped back to the file.
Json weld_json(const Input& in);
// The Session a command builds on the input runs on the operator the loader
// chose (or, unchecked, chooses it: load_input_for_session).
SessionOptions session_options(const Input& in);

// Up-front checks of -o for commands whose result a format cannot hold
// (Error(BadUsage) naming the alternative, before the input is read):
// results with texture coordinates refuse .off; commands whose result is only
// the JSON refuse -o altogether.
void check_uv_output(const CommonOptions& opt, const std::string& command);
void refuse_output(const CommonOptions& opt, const std::string& command, const std::string& result);

// Write options for an output on the input's vertices: the input file's
// vertex attributes with their types, float positions kept as float. Normals
// are dropped when the command moved the vertices; u/v when the result has
// UVs of its own (they replace them).
WriteOptions carried_attributes(const Input& in, bool positions_changed = false, bool result_uv = false);
// Adds a result property, replacing an input attribute of the same name.
void add_result(WriteOptions& wo, VertexProperty p);

// Writes `m` to -o FILE when one was given (format from the extension).
void write_output_mesh(const CommonOptions& opt, const Mesh& m, const WriteOptions& wo = {});

}  // namespace locus::cli
