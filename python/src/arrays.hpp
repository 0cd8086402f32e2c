// NumPy arrays in and out of the engine.
//
// In: positions as an (n, 3) float32 or float64 array and triangles as an
// (m, 3) int32, uint32, uint16 or int64 array. Rows at any positive stride with
// their three values adjacent (C order, or a row slice of it) are read in
// place through a MeshView, the one copy being the Session's own; any other
// layout (Fortran order, column slices) is first made C-contiguous, once.
// int64 ids are narrowed to int32 (an id beyond int32 is an InputError naming
// the face); the engine checks every id against the vertex count.
// Polygon meshes (polygon_mesh; the Session and the chapter-2 one-shots): an
// (m, k) array, a list of faces (each a sequence of ids) or a tuple
// (offsets, indices) in CSR form, offsets[0] = 0, len(offsets) = faces + 1.
//
// Out: results are NumPy arrays that take over the engine's std::vector (no
// copy): the array's base is a capsule owning the vector.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "locus/mesh.hpp"
#include "locus/mesh_view.hpp"
#include "locus/session.hpp"

namespace locus::python {

namespace py = pybind11;

// A MeshView over the caller's arrays, and what keeps them (or their
// converted copies) alive while the view is used.
struct TriangleArrays {
  MeshView view;
  py::array positions, triangles;
  std::vector<int32_t> narrowed;  // int64 ids as int32
};
TriangleArrays triangle_arrays(const py::handle& V, const py::handle& F);

// A polygon (or triangle) mesh as a locus::Mesh: F is an (m, k) array, a list of
// faces or (offsets, indices).
Mesh polygon_mesh(const py::handle& V, const py::handle& F);

// Positions only: (nv, 3) float32/float64 -> 3 * nv interleaved doubles.
std::vector<double> positions_xyz(const py::handle& V, int64_t nv, const char* name);

// A 1-D sequence of vertex ids (any integer dtype; a scalar is one id) as int32.
// Values beyond int32 raise ValueError naming the argument; the engine checks the range.
std::vector<int32_t> vertex_ids(const py::handle& ids, const char* name);

// Surface points: an int or 1-D integer array (vertices), or a tuple
// (faces, bary) of an (k,) integer array and a (k, 3) float array (a point
// in face f with barycentric weights of its corners, in the face's order).
std::vector<MeshPoint> mesh_points(const py::handle& points, const char* name);
// The inverse for face points: (faces (k,) int32, bary (k, 3) float64).
py::tuple face_points(const std::vector<MeshPoint>& points);

// A writable float64 array of `n` contiguous elements for an `out=` argument.
View<double> out_view(const py::handle& out, size_t n, const char* name);

// Takes over `v` as a NumPy array of the given shape (product = v.size()).
template <class T>
py::array_t<T> take(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), owner);
}
template <class T>
py::array_t<T> take(std::vector<T>&& v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return take(std::move(v), {n});
}
// A result in the host allocator's memory (HostVector): copied into a std::vector first.
template <class T>
py::array_t<T> take(HostVector<T>&& v) {
  return take(std::vector<T>(v.begin(), v.end()));
}

// A namespace object (types.SimpleNamespace) with the given attributes, the
// type of every structured result.
py::object result(const py::dict& fields);

}  // namespace locus::python
