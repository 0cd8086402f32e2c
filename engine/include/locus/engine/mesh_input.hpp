// The mesh a command works on, read from a file the way every front end reads
// it: locus::read_mesh (OFF, OBJ, PLY; the file's vertex attributes kept for
// the outputs), faces of more than three corners triangulated by ear clipping
// (kernels/mesh/polygon_triangulation) or kept for the commands that run on
// polygons, then 1:4 midpoint subdivision `subdivide` times (the contract's
// --subdivide, DESIGN.md "The command-line contract").
//
// Refusals, before anything large is allocated: Error(BadInput) for an
// unreadable file, a polygon that cannot be triangulated (naming the face) or
// subdividing a mesh whose polygons were kept; Error(BadUsage) when the
// subdivision would overflow 32-bit face indices; Error(ResourceLimit) when it
// would need more memory than the RunContext's limit. What the reader or the
// loader has to say (a PLY property it skipped, the triangulation, attributes
// dropped by the subdivision) goes to RunContext::note, never to a stream.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/engine/operator_choice.hpp"
#include "locus/export.h"
#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"
#include "locus/run_context.hpp"

LOCUS_API_BEGIN
namespace locus {

// What loading does with faces of more than 3 corners: triangulate them for
// the commands that need triangles, or keep them for those that take polygons.
enum class PolygonFaces { Triangulate, Keep };

struct LOCUS_API MeshInputOptions {
  int subdivide = 0;  // 1:4 midpoint subdivisions after loading, 0..16
  PolygonFaces faces = PolygonFaces::Triangulate;
  // Asset formats (read through assimp): weld the scene's vertices by position
  // (ReadOptions::weld); false keeps the file's vertices. OBJ, OFF, PLY: unused.
  bool weld = true;
  // The operator the command runs on (operator_choice.hpp); a Session made from
  // the input takes it (session_options), and the loader passes it on.
  OperatorChoice mesh_operator = OperatorChoice::Auto;
  // Look for the defects that choose the operator here (op below). false leaves
  // op unchecked: a Session made from the input with mesh_operator looks for them
  // in its own check, on the edge incidence it builds anyway (at 416k vertices
  // the loader's own incidence and report cost 0.35-0.65 s), and the caller copies
  // Session::operator_report() into op.
  bool choose_operator = true;
};

struct LOCUS_API MeshInput {
  std::string path;
  Mesh mesh;                  // what the command works on
  MeshAttributes attributes;  // the file's vertex attributes, carried to outputs on its vertices
  // When the file's polygons were triangulated: the file's faces on the same
  // vertices, and per triangle of `mesh` the file's face it belongs to.
  Mesh polygons;
  std::vector<int32_t> face_of;
  int subdivide = 0;
  OperatorChoice mesh_operator = OperatorChoice::Auto;  // as asked (MeshInputOptions)
  // The operator for the mesh worked on and why (choose_operator, after the
  // subdivision); not checked (op.checked false) for cotan or kept polygons.
  OperatorReport op;
  double load_s = 0;         // reading and parsing the file
  double triangulate_s = 0;  // polygons into triangles (0 when not needed)
  double subdivide_s = 0;    // the subdivision (0 when not asked)
  bool triangulated() const { return !face_of.empty(); }
  // The faces an output on the input's vertices is written with: the file's
  // polygons when they were triangulated, else the mesh worked on.
  const Mesh& output_faces() const { return triangulated() ? polygons : mesh; }
};

LOCUS_API MeshInput load_mesh_input(const std::string& path, const MeshInputOptions& opt = {},
                                    const RunContext& ctx = {});

}  // namespace locus
LOCUS_API_END
