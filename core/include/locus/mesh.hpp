// locus::Mesh — a polygon mesh as flat structure-of-arrays.
//
// Positions are three separate arrays; faces are CSR (face_offsets[nf+1] into
// face_vertices). When every face is a triangle, f0/f1/f2 hold the same faces
// as a fast path (empty otherwise). Vertex ids are 0-based in input order.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/core/host_allocator.hpp"

#include "locus/view.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct LOCUS_API Mesh {
  HostVector<double> x, y, z;               // nv each
  HostVector<int32_t> face_offsets{0};      // nf + 1
  HostVector<int32_t> face_vertices;        // face_offsets[nf]
  HostVector<int32_t> f0, f1, f2;           // nf each iff all faces are triangles
  std::string source;                        // file it came from, for messages ("" if generated)

  int32_t num_vertices() const { return static_cast<int32_t>(x.size()); }
  int32_t num_faces() const { return static_cast<int32_t>(face_offsets.size()) - 1; }
  bool is_triangle_mesh() const { return num_faces() == 0 || static_cast<int32_t>(f0.size()) == num_faces(); }
  ConstView<int32_t> face(int32_t f) const {
    return {face_vertices.data() + face_offsets[f], static_cast<size_t>(face_offsets[f + 1] - face_offsets[f])};
  }

  // Appends a face (polygon); keeps the triangle fast path consistent.
  void add_face(ConstView<int32_t> vs);
  void add_triangle(int32_t a, int32_t b, int32_t c);
  void add_vertex(double px, double py, double pz) { x.push_back(px); y.push_back(py); z.push_back(pz); }
  // Rebuilds f0/f1/f2 from the CSR faces (clears them if any face is not a triangle).
  void rebuild_triangle_arrays();
};

}  // namespace locus
LOCUS_API_END
