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
#include "locus/kernels/mesh/polygon_triangulation.hpp"

namespace locus {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Faces are indexed by int32 offsets (3 per triangle), and the subdivided
// mesh, its edge table and the topology analysis every command runs take
// about 130 bytes per resulting face (peak RSS of `locus info sphere.off
// --subdivide 9`: 11 GB for 84M faces): both refused before allocating.
void check_subdivision(const MeshInput& in, int times, const RunContext& ctx) {
  if (!in.mesh.is_triangle_mesh()) {
    int32_t f = 0;
    while (f < in.mesh.num_faces() && in.mesh.face(f).size() == 3) ++f;
    fail(ErrorCode::BadInput, "--subdivide needs a triangle mesh, but face " + std::to_string(f) + " of " + in.path +
                                  " has " + std::to_string(in.mesh.face(f).size()) + " vertices");
  }
  const double faces_after = in.mesh.num_faces() * std::pow(4.0, times);
  if (3.0 * faces_after > static_cast<double>(std::numeric_limits<int32_t>::max()))
    fail(ErrorCode::BadUsage, "--subdivide " + std::to_string(times) + " would make " +
                                  std::to_string(static_cast<long long>(faces_after)) + " faces from " + in.path +
                                  " (limit 715827882)");
  const double mesh_bytes = 130.0 * faces_after;
  if (mesh_bytes > static_cast<double>(memory_limit_bytes(ctx)))
    fail(ErrorCode::ResourceLimit, "--subdivide " + std::to_string(times) + " of " + in.path + " would need about " +
                                       format_number(mesh_bytes / 1073741824.0) + " GiB for its " +
                                       std::to_string(static_cast<long long>(faces_after)) +
                                       " faces, more than the memory limit of " +
                                       format_number(memory_limit_bytes(ctx) / 1073741824.0) +
                                       " GiB (raise it with --max-memory)");
}

}  // namespace

MeshInput load_mesh_input(const std::string& path, const MeshInputOptions& opt, const RunContext& ctx) {
  if (opt.subdivide < 0 || opt.subdivide > 16)
    fail(ErrorCode::BadUsage, "subdivide must be in 0..16 (got " + std::to_string(opt.subdivide) + ")");
  MeshInput in;
  in.path = path;
  in.subdivide = opt.subdivide;
  auto t0 = std::chrono::steady_clock::now();
  in.mesh = read_mesh(path, {}, &in.attributes);
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
    check_subdivision(in, opt.subdivide, ctx);
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
  return in;
}

}  // namespace locus
