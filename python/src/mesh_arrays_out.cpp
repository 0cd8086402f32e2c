// A locus::Mesh as NumPy arrays (mesh_arrays_out.hpp).
#include "mesh_arrays_out.hpp"

#include "arrays.hpp"

namespace py = pybind11;

namespace locus::python {

py::array positions_array(const Mesh& m) {
  const size_t nv = static_cast<size_t>(m.num_vertices());
  std::vector<double> xyz(3 * nv);
  for (size_t i = 0; i < nv; ++i) {
    xyz[3 * i] = m.x[i];
    xyz[3 * i + 1] = m.y[i];
    xyz[3 * i + 2] = m.z[i];
  }
  return take(std::move(xyz), {py::ssize_t(nv), 3});
}

py::object faces_object(const Mesh& m) {
  const int32_t nf = m.num_faces();
  if (m.is_triangle_mesh()) {
    std::vector<int32_t> f(3 * static_cast<size_t>(nf));
    for (int32_t i = 0; i < nf; ++i) {
      f[3 * i] = m.f0[i];
      f[3 * i + 1] = m.f1[i];
      f[3 * i + 2] = m.f2[i];
    }
    return take(std::move(f), {py::ssize_t(nf), 3});
  }
  // Every face of one size k: an (nf, k) array, as NumPy code indexes faces;
  // mixed sizes: a list of int32 arrays (one per face).
  const int32_t k = nf > 0 ? static_cast<int32_t>(m.face(0).size()) : 0;
  bool uniform = nf > 0;
  for (int32_t i = 1; i < nf && uniform; ++i) uniform = static_cast<int32_t>(m.face(i).size()) == k;
  if (uniform) {
    std::vector<int32_t> f;
    f.reserve(static_cast<size_t>(nf) * static_cast<size_t>(k));
    for (int32_t i = 0; i < nf; ++i) {
      const ConstView<int32_t> face = m.face(i);
      f.insert(f.end(), face.begin(), face.end());
    }
    return take(std::move(f), {py::ssize_t(nf), py::ssize_t(k)});
  }
  py::list faces;
  for (int32_t i = 0; i < nf; ++i) {
    const ConstView<int32_t> face = m.face(i);
    faces.append(take(std::vector<int32_t>(face.begin(), face.end())));
  }
  return faces;
}

}  // namespace locus::python
