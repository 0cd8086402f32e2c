// The region of a localized heat geodesic query (pipelines/include/locus/pipelines/geodesic/heat_geodesic.hpp,
// PatchRegion; thesis §6.4.2): the patch P, its one ring and the triangles
// touching P, with each triangle's corners as indices into that list. Built
// per query from the vertex-face records of HeatGeodesic in O(|P| + |ring|)
// (plus O(n / 64) words cleared), released so that the n-sized index array is
// all -1 again and the next query touches only its own region.
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "heat_geodesic_limits.hpp"

#include <string>

#include "locus/core/bit_set.hpp"
#include "locus/error.hpp"

namespace locus {

using heat_geodesic_limits::kAhead;

void HeatGeodesic::build_region(std::span<const int32_t> patch, PatchRegion& r) const {
  const int32_t n = grad_.nv;
  if (r.local.size() != static_cast<size_t>(n)) r.local.assign(n, -1);
  r.verts.clear();
  r.faces.clear();
  r.face_local.clear();
  if (patch.empty()) fail(ErrorCode::BadUsage, "the patch is empty");
  for (size_t k = 0; k < patch.size(); ++k) {
    const int32_t v = patch[k];
    if (k + static_cast<size_t>(kAhead) < patch.size() && static_cast<uint32_t>(patch[k + static_cast<size_t>(kAhead)]) < static_cast<uint32_t>(n))
      __builtin_prefetch(r.local.data() + patch[k + static_cast<size_t>(kAhead)], 1);
    if (v < 0 || v >= n || r.local[v] >= 0) {
      const bool dup = v >= 0 && v < n;
      release_region(r);
      fail(ErrorCode::BadUsage, "patch entry " + std::to_string(k) + " is vertex " + std::to_string(v) +
                                    (dup ? ", listed twice" : ", outside 0.." + std::to_string(n - 1)));
    }
    r.local[v] = static_cast<int32_t>(r.verts.size());
    r.verts.push_back(v);
  }
  const int32_t np = static_cast<int32_t>(patch.size());
  r.patch_size = np;
  // A face is listed once, by its owner: the patch corner in the lowest corner
  // slot. The patch is fully marked above, so ownership is decided from the
  // corner records alone (no per-face marks to set and reset: random writes).
  auto in_patch = [&](int32_t w) { return static_cast<uint32_t>(r.local[w]) < static_cast<uint32_t>(np); };
  // Patch vertices lie scattered in memory (a subdivided mesh numbers the new
  // vertices after the old ones), so each one's records are a cache miss; they
  // are known in advance and fetched ahead in two stages (offsets, then records).
  // The walk goes in ascending vertex order (the patch's bits in an n-bit set,
  // read off word by word), so the per-vertex records are read in memory order:
  // at 50 % of a 416k mesh the caller's (Dijkstra) order made every vertex a
  // cache miss. Faces and ring vertices are therefore listed in that order.
  r.order.clear();
  if (r.bits.size() != bit_words(n)) r.bits.assign(bit_words(n), 0);
  if (r.face_bits.size() != bit_words(grad_.nf)) r.face_bits.assign(bit_words(grad_.nf), 0);
  for (int32_t k = 0; k < np; ++k) set_bit(r.bits, r.verts[k]);
  append_set_bits(r.bits, r.order);
  std::fill(r.bits.begin(), r.bits.end(), 0);
  for (int32_t k = 0; k < np; ++k) {
    if (k + 2 * kAhead < np) __builtin_prefetch(grad_.vf_offsets.data() + r.order[k + 2 * kAhead]);
    if (k + kAhead < np) __builtin_prefetch(vf_corners_.data() + 4 * grad_.vf_offsets[r.order[k + kAhead]]);
    const int32_t v = r.order[k];
    for (int64_t q = grad_.vf_offsets[v]; q < grad_.vf_offsets[v + 1]; ++q) {
      const int32_t* c = vf_corners_.data() + 4 * q;  // the face's corners in slot order, then the face
      if (c[0] != v && (in_patch(c[0]) || (c[1] != v && in_patch(c[1])))) continue;
      const int32_t f = c[3];
      set_bit(r.face_bits, f);
      for (int s = 0; s < 3; ++s) {
        const int32_t w = c[s];
        if (r.local[w] < 0) {
          r.local[w] = static_cast<int32_t>(r.verts.size());
          r.verts.push_back(w);
        }
      }
    }
  }
  build_region_faces(r);
}

void HeatGeodesic::build_region_faces(PatchRegion& r) const {
  // Faces in ascending order too: the divergence then reads their gradient
  // bases (72 bytes each) in memory order.
  r.faces.clear();
  append_set_bits(r.face_bits, r.faces);
  std::fill(r.face_bits.begin(), r.face_bits.end(), 0);
  // Corner indices into verts; the corners' entries of `local` are fetched ahead.
  const size_t nfl = r.faces.size();
  r.face_local.resize(3 * nfl);
  for (size_t q = 0; q < nfl; ++q) {
    if (q + kAhead < nfl) {
      const int32_t* ta = grad_.tri.data() + 3 * static_cast<int64_t>(r.faces[q + kAhead]);
      for (int s = 0; s < 3; ++s) __builtin_prefetch(r.local.data() + ta[s]);
    }
    const int32_t* t = grad_.tri.data() + 3 * static_cast<int64_t>(r.faces[q]);
    for (int s = 0; s < 3; ++s) r.face_local[3 * q + s] = r.local[t[s]];
  }
}

void HeatGeodesic::release_region(PatchRegion& r) const {
  for (int32_t v : r.verts) r.local[v] = -1;
  r.verts.clear();
  r.faces.clear();
  r.face_local.clear();
  r.patch_size = 0;
}

}  // namespace locus
