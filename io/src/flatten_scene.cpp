// Scene flattening for asset files (io/include/locus/io/flatten_scene.hpp).
//
// A game or DCC asset is a node tree: each node has a local transform and
// references meshes. The surface the artist sees is every node's meshes
// placed by the node's global transform (parent * ... * local), which is what
// is assembled here, in double precision (assimp stores float matrices and
// positions; composing in double keeps deep hierarchies from accumulating
// float rounding). A mesh referenced by two nodes appears twice. Points and
// lines are not surface: they are skipped and counted, as are meshes holding
// nothing else. Welding (weld_vertices.hpp) then merges the copies exporters
// make of a vertex at UV and normal seams; a triangle whose corners become
// one vertex (or that repeats a corner in the file) is dropped and counted.
#include "locus/io/flatten_scene.hpp"

#include <assimp/scene.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/io/mesh_checks.hpp"
#include "locus/io/weld_vertices.hpp"

namespace locus::io {
namespace {

using Affine = std::array<double, 12>;  // row-major 3x4: [R | t]

Affine to_affine(const aiMatrix4x4& m) {
  return {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
}

Affine compose(const Affine& p, const Affine& l) {  // p * l
  Affine r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? p[size_t(i * 4 + 3)] : 0.0;
      for (int k = 0; k < 3; ++k) s += p[size_t(i * 4 + k)] * l[size_t(k * 4 + j)];
      r[size_t(i * 4 + j)] = s;
    }
  }
  return r;
}

struct Instance {
  const aiMesh* mesh;
  uint32_t mesh_index;
  const aiNode* node;
  Affine xf;
};

std::string node_name(const aiNode* n) { return n->mName.length ? std::string(n->mName.C_Str()) : "(unnamed)"; }

// Every (node, mesh) pair, depth first in file order, with the node's global
// transform. Iterative: a hostile file's deep hierarchy cannot overflow the stack.
std::vector<Instance> collect_instances(const aiScene& scene, const std::string& name) {
  std::vector<Instance> out;
  if (!scene.mRootNode) return out;
  struct Item {
    const aiNode* node;
    Affine parent;
  };
  const Affine identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::vector<Item> stack{{scene.mRootNode, identity}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const Affine g = compose(it.parent, to_affine(it.node->mTransformation));
    for (unsigned k = 0; k < it.node->mNumMeshes; ++k) {
      const unsigned mi = it.node->mMeshes[k];
      if (mi >= scene.mNumMeshes || !scene.mMeshes[mi])
        fail(ErrorCode::BadInput, name + ": node '" + node_name(it.node) + "' references mesh " + std::to_string(mi) +
                                      " but the scene has " + std::to_string(scene.mNumMeshes) + " meshes");
      out.push_back({scene.mMeshes[mi], mi, it.node, g});
    }
    for (unsigned c = it.node->mNumChildren; c-- > 0;)
      if (it.node->mChildren[c]) stack.push_back({it.node->mChildren[c], g});
  }
  return out;
}

std::string where(const Instance& in) {
  std::string mesh = in.mesh->mName.length ? std::string(in.mesh->mName.C_Str()) : "(unnamed)";
  return "mesh " + std::to_string(in.mesh_index) + " '" + mesh + "' of node '" + node_name(in.node) + "'";
}

// Counts the primitives of one mesh: triangles kept, points and lines skipped.
uint64_t count_triangles(const aiMesh& m, AssetReport& report) {
  uint64_t tris = 0;
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const unsigned k = m.mFaces[f].mNumIndices;
    if (k == 3) ++tris;
    else if (k == 1) ++report.skipped_points;
    else if (k == 2) ++report.skipped_lines;
  }
  return tris;
}

// The triangles of the kept meshes through the file vertex -> mesh vertex
// map; a triangle with a repeated corner is dropped and counted.
void append_triangles(const std::vector<Instance>& kept, const std::vector<int32_t>& map, uint64_t nf,
                      const std::string& name, Mesh& m, AssetReport& report) {
  m.face_offsets.reserve(size_t(nf) + 1);
  m.face_vertices.reserve(size_t(nf) * 3);
  int32_t base = 0;
  for (const Instance& in : kept) {
    const aiMesh& am = *in.mesh;
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) continue;
      int32_t c[3];
      for (int k = 0; k < 3; ++k) {
        const unsigned i = face.mIndices[k];
        if (i >= am.mNumVertices)
          fail(ErrorCode::BadInput, name + ": " + where(in) + ": face " + std::to_string(f) + " references vertex " +
                                        std::to_string(i) + " but the mesh has " + std::to_string(am.mNumVertices));
        c[k] = map[size_t(base) + i];
      }
      if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
        ++report.collapsed_faces;
        continue;
      }
      m.face_vertices.insert(m.face_vertices.end(), c, c + 3);
      m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
    }
    base += static_cast<int32_t>(am.mNumVertices);
  }
}

}  // namespace

Mesh flatten_scene(const aiScene& scene, const std::string& name, const ReadOptions& opt, AssetReport& report) {
  report = {};
  std::vector<Instance> all = collect_instances(scene, name);
  // The sizes first, before any per-vertex allocation (saturating sums).
  std::vector<Instance> kept;
  uint64_t nv = 0, nf = 0;
  for (const Instance& in : all) {
    const uint64_t tris = count_triangles(*in.mesh, report);
    if (tris == 0 || in.mesh->mNumVertices == 0 || !in.mesh->mVertices) {
      ++report.skipped_meshes;
      continue;
    }
    kept.push_back(in);
    nv = sat_add(nv, in.mesh->mNumVertices);
    nf = sat_add(nf, tris);
  }
  if (kept.empty())
    fail(ErrorCode::BadInput, name + ": the scene has no triangles (" + std::to_string(all.size()) +
                                  " node meshes, " + std::to_string(report.skipped_points) + " points and " +
                                  std::to_string(report.skipped_lines) + " lines skipped)");
  // Beyond the mesh arrays: the file positions, the map and the weld's sort
  // (3 doubles and 3 int32 per file vertex).
  const uint64_t need = sat_add(mesh_bytes(nv, nf, sat_mul(nf, 3)), sat_mul(nv, 3 * sizeof(double) + 12));
  if (need > opt.max_bytes)
    fail(ErrorCode::ResourceLimit, name + ": the flattened scene has " + std::to_string(nv) + " vertices and " +
                                       std::to_string(nf) + " triangles, which would need " + std::to_string(need) +
                                       " bytes, more than the limit of " + std::to_string(opt.max_bytes) +
                                       " bytes (ReadOptions::max_bytes)");
  if (nv > uint64_t(std::numeric_limits<int32_t>::max()) || nf > uint64_t(std::numeric_limits<int32_t>::max()))
    fail(ErrorCode::ResourceLimit, name + ": the flattened scene has " + std::to_string(nv) + " vertices and " +
                                       std::to_string(nf) + " triangles, more than a mesh can index (2^31 - 1)");

  std::vector<double> x, y, z;
  x.reserve(nv), y.reserve(nv), z.reserve(nv);
  for (const Instance& in : kept) {
    const Affine& a = in.xf;
    for (unsigned v = 0; v < in.mesh->mNumVertices; ++v) {
      const aiVector3D& p = in.mesh->mVertices[v];
      const double px = p.x, py = p.y, pz = p.z;
      const double qx = a[0] * px + a[1] * py + a[2] * pz + a[3];
      const double qy = a[4] * px + a[5] * py + a[6] * pz + a[7];
      const double qz = a[8] * px + a[9] * py + a[10] * pz + a[11];
      const std::string bad = vertex_problem(v, qx, qy, qz);
      if (!bad.empty()) fail(ErrorCode::BadInput, name + ": " + where(in) + ": " + bad + " after the node transform");
      x.push_back(qx), y.push_back(qy), z.push_back(qz);
    }
  }

  report.mesh_instances = static_cast<int32_t>(kept.size());
  report.file_vertices = static_cast<int64_t>(nv);
  std::vector<int32_t>& map = report.file_to_vertex;
  Mesh m;
  if (opt.weld) {
    const int32_t nw = weld_by_position(x, y, z, map);
    m.x.resize(size_t(nw)), m.y.resize(size_t(nw)), m.z.resize(size_t(nw));
    for (size_t i = 0; i < map.size(); ++i) {
      const size_t w = size_t(map[i]);
      m.x[w] = x[i], m.y[w] = y[i], m.z[w] = z[i];  // copies are equal: any one will do
    }
    report.welded_vertices = static_cast<int64_t>(nv) - nw;
  } else {
    map.resize(size_t(nv));
    for (size_t i = 0; i < map.size(); ++i) map[i] = int32_t(i);
    m.x.assign(x.begin(), x.end()), m.y.assign(y.begin(), y.end()), m.z.assign(z.begin(), z.end());
  }
  x = {}, y = {}, z = {};

  append_triangles(kept, map, nf, name, m, report);
  if (m.num_faces() == 0)
    fail(ErrorCode::BadInput, name + ": every triangle of the scene repeats a corner (" +
                                  std::to_string(report.collapsed_faces) + " degenerate triangles)");
  finish_mesh(m, name);
  return m;
}

}  // namespace locus::io
