// The format-independent rules every mesh reader enforces (mesh_io.hpp):
// finite coordinates, faces with at least 3 pairwise distinct vertices, counts
// a Mesh can index, and the allocation budget of ReadOptions::max_bytes.
// Internal to io/. Topological questions (manifoldness, zero areas,
// components) are deliberately not here: those belong to mesh_topology.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "locus/io/text_scanner.hpp"
#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"

namespace locus::io {

// Empty string when the vertex is fine, otherwise what is wrong with it.
inline std::string vertex_problem(int64_t v, double x, double y, double z) {
  if (std::isfinite(x) && std::isfinite(y) && std::isfinite(z)) return {};
  return "vertex " + std::to_string(v) + " has a non-finite coordinate (" + coord_text(x) + ", " + coord_text(y) +
         ", " + coord_text(z) + ")";
}

// Parses one coordinate token of vertex v. Empty string on success, otherwise
// the problem: not a number, or a number too large for a double (which we
// report as non-finite, like an explicit "inf").
inline std::string parse_coordinate(std::string_view tok, int64_t v, double& out) {
  if (parse_double(tok, out)) return {};
  const char* b = tok.data() + (!tok.empty() && tok[0] == '+');
  double probe;
  if (!tok.empty() && std::from_chars(b, tok.data() + tok.size(), probe).ec == std::errc::result_out_of_range)
    return "vertex " + std::to_string(v) + " has a non-finite coordinate " + quote(tok) + " (overflows a double)";
  return "vertex " + std::to_string(v) + ": expected a number, found " + quote(tok);
}

// Empty string when the face is fine, otherwise what is wrong with it. Indices
// are already range-checked by the reader (it knows the line / offset).
inline std::string face_problem(int64_t f, std::span<const int32_t> vs) {
  if (vs.size() < 3)
    return "face " + std::to_string(f) + " has " + std::to_string(vs.size()) +
           " vertices (a face needs at least 3)";
  // Repeated vertices: quadratic is fastest for the usual 3..8 corners; big
  // polygons (possible in hostile files) are sorted instead, so this stays
  // O(k log k) whatever the input.
  if (vs.size() <= 16) {
    for (size_t i = 0; i < vs.size(); ++i)
      for (size_t j = i + 1; j < vs.size(); ++j)
        if (vs[i] == vs[j])
          return "face " + std::to_string(f) + " uses vertex " + std::to_string(vs[i]) +
                 " twice (repeated vertex in one face)";
    return {};
  }
  std::vector<int32_t> s(vs.begin(), vs.end());
  std::sort(s.begin(), s.end());
  const auto it = std::adjacent_find(s.begin(), s.end());
  if (it != s.end())
    return "face " + std::to_string(f) + " uses vertex " + std::to_string(*it) + " twice (repeated vertex in one face)";
  return {};
}

// Bytes the Mesh arrays need for nv vertices, nf faces and `corners` face
// corners (face_vertices), including the triangle fast path.
inline uint64_t mesh_bytes(uint64_t nv, uint64_t nf, uint64_t corners) {
  uint64_t b = sat_mul(nv, 3 * sizeof(double));
  b = sat_add(b, sat_mul(sat_add(nf, 1), sizeof(int32_t)));
  b = sat_add(b, sat_mul(corners, sizeof(int32_t)));
  b = sat_add(b, sat_mul(nf, 3 * sizeof(int32_t)));
  return b;
}

// Refuses (ResourceLimit) a mesh whose arrays would exceed opt.max_bytes;
// called with header counts before anything is allocated.
inline void check_budget(const std::string& name, uint64_t nv, uint64_t nf, uint64_t corners, const ReadOptions& opt) {
  const uint64_t need = mesh_bytes(nv, nf, corners);
  if (need > opt.max_bytes)
    fail(ErrorCode::ResourceLimit, name + ": " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                       " faces would need " + std::to_string(need) +
                                       " bytes, more than the limit of " + std::to_string(opt.max_bytes) +
                                       " bytes (ReadOptions::max_bytes)");
}

// Final step of every reader: at least one vertex, and the triangle fast path.
inline void finish_mesh(Mesh& m, const std::string& name) {
  if (m.x.empty()) fail(ErrorCode::BadInput, name + ": the file has no vertices");
  m.source = name;
  m.rebuild_triangle_arrays();
}

}  // namespace locus::io
