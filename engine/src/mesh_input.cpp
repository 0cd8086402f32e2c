// Loading a command's mesh from a file (engine/include/locus/engine/mesh_input.hpp):
// read, triangulate or keep polygons, subdivide, each step timed.
#include "locus/engine/mesh_input.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "locus/engine/heat_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/factor/memory_budget.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/subdivision_budget.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"

namespace locus {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Refused before allocating: face indices beyond int32 (exit 3) or more memory
// than the limit for the mesh and its derived data (kernels' subdivision_budget.hpp).
void check_subdivision_of(const MeshInput& in, int times, const RunContext& ctx) {
  if (!in.mesh.is_triangle_mesh()) {
    int32_t f = 0;
    while (f < in.mesh.num_faces() && in.mesh.face(f).size() == 3) ++f;
    fail(ErrorCode::BadInput, "--subdivide needs a triangle mesh, but face " + std::to_string(f) + " of " + in.path +
                                  " has " + std::to_string(in.mesh.face(f).size()) + " vertices");
  }
  try {
    check_subdivision(in.mesh, times, ctx);
  } catch (const Error& e) {
    fail(e.code(), "--subdivide " + std::to_string(times) + ": " + e.what());
  }
}

}  // namespace

MeshInput load_mesh_input(const std::string& path, const MeshInputOptions& opt, const RunContext& ctx) {
  if (opt.subdivide < 0 || opt.subdivide > 16)
    fail(ErrorCode::BadUsage, "subdivide must be in 0..16 (got " + std::to_string(opt.subdivide) + ")");
  MeshInput in;
  in.path = path;
  in.subdivide = opt.subdivide;
  in.mesh_operator = opt.mesh_operator;
  auto t0 = std::chrono::steady_clock::now();
  ReadOptions ro;
  ro.weld = opt.weld;
  in.mesh = read_mesh(path, ro, &in.attributes);
  in.load_s = seconds_since(t0);
  for (const std::string& note : in.attributes.notes) ctx.note(note);
  if (opt.faces == PolygonFaces::Triangulate && !in.mesh.is_triangle_mesh()) {
    ctx.check_cancel();
    t0 = std::chrono::steady_clock::now();
    TriangulatedMesh t = triangulate_polygons(in.mesh, path);
    in.polygons = std::move(in.mesh);
    in.mesh = std::move(t.mesh);
    in.face_of = std::move(t.face_of);
    in.triangulate_s = seconds_since(t0);
    ctx.note("triangulated the " + std::to_string(in.polygons.num_faces()) + " faces of " + path + " into " +
             std::to_string(in.mesh.num_faces()) + " triangles (ear clipping); outputs on its vertices keep its faces");
  }
  if (opt.subdivide > 0) {
    ctx.check_cancel();
    check_subdivision_of(in, opt.subdivide, ctx);
    if (!in.attributes.vertex.empty()) {
      ctx.note("--subdivide: the input's " + std::to_string(in.attributes.vertex.size()) +
               " vertex attribute(s) are not carried to the outputs (subdivision makes new vertices)");
      in.attributes.vertex.clear();
    }
    if (in.triangulated()) {  // new vertices: the file's faces no longer describe the mesh
      in.polygons = Mesh{};
      in.face_of.clear();
    }
    t0 = std::chrono::steady_clock::now();
    in.mesh = subdivide_midpoint(in.mesh, opt.subdivide);
    in.subdivide_s = seconds_since(t0);
  }
  in.op.asked = opt.mesh_operator;
  if (opt.choose_operator && opt.mesh_operator != OperatorChoice::Cotan && in.mesh.is_triangle_mesh() &&
      in.mesh.num_faces() > 0) {
    in.op = choose_operator(in.mesh, opt.mesh_operator);
    if (in.op.robust && in.op.any_defect())
      ctx.note(path + ": the robust operator (" + in.op.reason() + ")");
  }
  return in;
}

}  // namespace locus
