// Mesh construction helpers (core/include/locus/mesh.hpp).
#include "locus/mesh.hpp"

namespace locus {

void Mesh::add_face(ConstView<int32_t> vs) {
  const bool was_tri = is_triangle_mesh();
  face_vertices.insert(face_vertices.end(), vs.begin(), vs.end());
  face_offsets.push_back(static_cast<int32_t>(face_vertices.size()));
  if (was_tri && vs.size() == 3) {
    f0.push_back(vs[0]); f1.push_back(vs[1]); f2.push_back(vs[2]);
  } else {
    f0.clear(); f1.clear(); f2.clear();
  }
}

void Mesh::add_triangle(int32_t a, int32_t b, int32_t c) {
  const int32_t t[3] = {a, b, c};
  add_face(t);
}

void Mesh::rebuild_triangle_arrays() {
  f0.clear(); f1.clear(); f2.clear();
  const int32_t nf = num_faces();
  for (int32_t f = 0; f < nf; ++f)
    if (face_offsets[f + 1] - face_offsets[f] != 3) return;
  f0.resize(nf); f1.resize(nf); f2.resize(nf);
  for (int32_t f = 0; f < nf; ++f) {
    const int32_t* v = face_vertices.data() + face_offsets[f];
    f0[f] = v[0]; f1[f] = v[1]; f2[f] = v[2];
  }
}

}  // namespace locus
