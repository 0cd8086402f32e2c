// A triangle mesh's face_vertices set aside while nothing reads them (thesis
// §3.7.1: from the assembly of the cells' operator M - tL to the end of the
// repair, the factorization reads the operator only, and Lloyd, the incidence's
// rebuild, the restricted dual and the repair's rounds read the faces through
// f0/f1/f2, which hold the same triangles). At 416k vertices the corners are
// 10 MB of a remesh's peak; rebuilding them from f0/f1/f2 is one pass.
// Internal to the engine: only for a mesh nobody else reads meanwhile
// (SessionOptions::exclusive).
#pragma once
#include "locus/mesh.hpp"

namespace locus {

class FaceCornerLoan {
 public:
  explicit FaceCornerLoan(Mesh& m) : m_(m) {}
  FaceCornerLoan(const FaceCornerLoan&) = delete;
  FaceCornerLoan& operator=(const FaceCornerLoan&) = delete;
  // Restores what was released (the owner may read the faces after an error).
  ~FaceCornerLoan();

  // Frees m.face_vertices of a triangle mesh with faces (nothing otherwise).
  void release();
  // m.face_vertices as they were: f0[f], f1[f], f2[f] per face. Nothing when
  // not released.
  void restore();
  bool released() const { return released_; }

 private:
  Mesh& m_;
  bool released_ = false;
};

}  // namespace locus
