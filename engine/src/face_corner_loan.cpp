// A triangle mesh's corners set aside and rebuilt (face_corner_loan.hpp; thesis §3.7.1).
#include "face_corner_loan.hpp"

namespace locus {

FaceCornerLoan::~FaceCornerLoan() {
  try {
    restore();
  } catch (...) {  // out of memory while unwinding: the owner's corners stay empty
  }
}

void FaceCornerLoan::release() {
  if (released_ || m_.num_faces() == 0 || !m_.is_triangle_mesh()) return;
  m_.face_vertices = HostVector<int32_t>{};
  released_ = true;
}

void FaceCornerLoan::restore() {
  if (!released_) return;
  const int32_t nf = m_.num_faces();
  HostVector<int32_t> fv(3 * static_cast<size_t>(nf));
  for (int32_t f = 0; f < nf; ++f) {
    fv[3 * static_cast<size_t>(f)] = m_.f0[f];
    fv[3 * static_cast<size_t>(f) + 1] = m_.f1[f];
    fv[3 * static_cast<size_t>(f) + 2] = m_.f2[f];
  }
  m_.face_vertices = std::move(fv);
  released_ = false;
}

}  // namespace locus
