// NumPy arrays in and out of the engine; arrays.hpp says
// which layouts are read in place and which are converted once.
#include "arrays.hpp"

#include <cmath>
#include <limits>

#include "errors.hpp"

namespace locus::python {
namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

py::array as_array(const py::handle& h, const char* name) {
  if (h.is_none()) usage_error(std::string(name) + " is None");
  try {
    return numpy().attr("asarray")(h);
  } catch (py::error_already_set&) {
    usage_error(std::string(name) + " is not an array");
  }
}

// Rows of three adjacent native-endian values at a positive stride: readable in place.
bool rows_in_place(const py::array& a) {
  const auto item = static_cast<py::ssize_t>(a.itemsize());
  return a.dtype().attr("isnative").cast<bool>() && a.strides(1) == item && a.strides(0) >= 3 * item;
}

py::array c_contiguous(const py::array& a, const py::object& dtype) {
  return numpy().attr("ascontiguousarray")(a, py::arg("dtype") = dtype);
}

py::array rows_of_three(const py::handle& h, const char* name) {
  py::array a = as_array(h, name);
  if (a.ndim() != 2 || a.shape(1) != 3)
    usage_error(std::string(name) + " must have shape (n, 3), got " + shape_text(a));
  return a;
}

// int64 (and other wide or narrow integer) ids as int32; out-of-int32 values are an InputError.
std::vector<int32_t> narrow_ids(const py::array& a, const char* name, const char* row_name) {
  const py::array wide = c_contiguous(a, numpy().attr("int64"));
  const auto* p = static_cast<const int64_t*>(wide.data());
  const auto n = static_cast<size_t>(wide.size());
  std::vector<int32_t> out(n);
  const py::ssize_t width = a.ndim() == 2 ? a.shape(1) : 1;
  for (size_t i = 0; i < n; ++i) {
    if (p[i] < std::numeric_limits<int32_t>::min() || p[i] > std::numeric_limits<int32_t>::max())
      input_error(std::string(name) + ": " + row_name + " " + std::to_string(i / width) + " references vertex " +
                  std::to_string(p[i]) + ", beyond the int32 ids locus uses");
    out[i] = static_cast<int32_t>(p[i]);
  }
  return out;
}

void require_integers(const py::array& a, const char* name) {
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    usage_error(std::string(name) + " must hold integer ids (int32, int64 or uint32), got " + dtype_text(a));
  if (kind == 'u' && a.itemsize() == 8) {
    // uint64 beyond int64 would wrap in the int64 conversion: reject first.
    if (a.size() > 0 && numpy().attr("max")(a).cast<uint64_t>() > uint64_t(std::numeric_limits<int32_t>::max()))
      input_error(std::string(name) + ": a vertex id is beyond the int32 ids locus uses");
  }
}

}  // namespace

TriangleArrays triangle_arrays(const py::handle& V, const py::handle& F) {
  TriangleArrays t;
  t.positions = rows_of_three(V, "V");
  if (t.positions.dtype().kind() != 'f' || (t.positions.itemsize() != 4 && t.positions.itemsize() != 8))
    usage_error("V must be float32 or float64, got " + dtype_text(t.positions));
  if (!rows_in_place(t.positions))
    t.positions = c_contiguous(t.positions, t.positions.dtype().attr("newbyteorder")("="));
  t.view.positions = t.positions.data();
  t.view.position_type = t.positions.itemsize() == 4 ? ScalarType::Float32 : ScalarType::Float64;
  t.view.position_stride = t.positions.strides(0);
  t.view.vertex_count = t.positions.shape(0);

  t.triangles = as_array(F, "F");
  if (t.triangles.ndim() != 2 || t.triangles.shape(1) != 3)
    usage_error("F must have shape (m, 3) (triangles) or be a polygon mesh ((m, k) array, list of faces or "
                "(offsets, indices)), got " +
                shape_text(t.triangles));
  require_integers(t.triangles, "F");
  const char kind = t.triangles.dtype().kind();
  const auto item = t.triangles.itemsize();
  const bool viewable = (item == 4) || (kind == 'u' && item == 2);
  if (viewable) {
    if (!rows_in_place(t.triangles))
      t.triangles = c_contiguous(t.triangles, t.triangles.dtype().attr("newbyteorder")("="));
    t.view.indices = t.triangles.data();
    t.view.index_type = item == 2 ? IndexType::UInt16 : kind == 'u' ? IndexType::UInt32 : IndexType::Int32;
    t.view.index_stride = t.triangles.strides(0);
  } else {
    t.narrowed = narrow_ids(t.triangles, "F", "face");
    t.view.indices = t.narrowed.data();
    t.view.index_type = IndexType::Int32;
    t.view.index_stride = 0;
  }
  t.view.triangle_count = t.triangles.shape(0);
  return t;
}

std::vector<double> positions_xyz(const py::handle& V, int64_t nv, const char* name) {
  py::array a = rows_of_three(V, name);
  if (a.dtype().kind() != 'f') usage_error(std::string(name) + " must be float32 or float64, got " + dtype_text(a));
  if (nv >= 0 && a.shape(0) != nv)
    usage_error(std::string(name) + " has " + std::to_string(a.shape(0)) + " rows, expected " + std::to_string(nv) +
                " (one per vertex)");
  const py::array d = c_contiguous(a, numpy().attr("float64"));
  const auto* p = static_cast<const double*>(d.data());
  return std::vector<double>(p, p + d.size());
}

Mesh polygon_mesh(const py::handle& V, const py::handle& F) {
  Mesh m;
  const std::vector<double> xyz = positions_xyz(V, -1, "V");
  for (size_t i = 0; i + 2 < xyz.size(); i += 3) m.add_vertex(xyz[i], xyz[i + 1], xyz[i + 2]);
  for (double c : xyz)
    if (!std::isfinite(c)) input_error("V holds a non-finite coordinate");
  std::vector<int32_t> offsets, ids;
  if (py::isinstance<py::tuple>(F) && py::len(F) == 2) {  // (offsets, indices)
    offsets = vertex_ids(F[py::int_(0)], "F offsets");
    ids = vertex_ids(F[py::int_(1)], "F indices");
  } else if (py::isinstance<py::list>(F)) {  // a list of faces
    offsets.push_back(0);
    for (const py::handle face : F) {
      const std::vector<int32_t> f = vertex_ids(face, "F face");
      ids.insert(ids.end(), f.begin(), f.end());
      offsets.push_back(static_cast<int32_t>(ids.size()));
    }
  } else {  // an (m, k) array: m faces of k vertices
    const py::array a = as_array(F, "F");
    if (a.ndim() != 2 || a.shape(1) < 3) usage_error("F must have shape (m, k) with k >= 3, got " + shape_text(a));
    ids = vertex_ids(numpy().attr("ravel")(a), "F");
    for (py::ssize_t f = 0; f <= a.shape(0); ++f) offsets.push_back(static_cast<int32_t>(f * a.shape(1)));
  }
  if (offsets.empty() || offsets.front() != 0 || offsets.back() != static_cast<int32_t>(ids.size()))
    usage_error("F offsets must start at 0 and end at len(indices)");
  for (size_t f = 0; f + 1 < offsets.size(); ++f) {
    if (offsets[f + 1] - offsets[f] < 3)
      input_error("face " + std::to_string(f) + " has " + std::to_string(offsets[f + 1] - offsets[f]) +
                  " vertices (at least 3 needed)");
    for (int32_t k = offsets[f]; k < offsets[f + 1]; ++k)
      if (ids[k] < 0 || ids[k] >= m.num_vertices())
        input_error("face " + std::to_string(f) + " references vertex " + std::to_string(ids[k]) + " but V has " +
                    std::to_string(m.num_vertices()) + " vertices");
    m.add_face(ConstView<int32_t>(ids.data() + offsets[f], size_t(offsets[f + 1] - offsets[f])));
  }
  return m;
}

int32_t vertex_id(const py::handle& v, int64_t nv, const std::string& what) {
  PyObject* index = PyNumber_Index(v.ptr());
  if (!index) {
    PyErr_Clear();
    usage_error(what + " must be a vertex id (an integer), got " + py::str(py::type::of(v)).cast<std::string>());
  }
  const py::object owned = py::reinterpret_steal<py::object>(index);
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(index, &overflow);
  if (overflow != 0 || x < 0 || x >= nv)
    usage_error(what + " " + py::str(owned).cast<std::string>() + " is not a vertex (0.." + std::to_string(nv - 1) +
                ")");
  return static_cast<int32_t>(x);
}

std::vector<int32_t> vertex_ids(const py::handle& ids, const char* name) {
  py::array a = as_array(ids, name);
  if (a.ndim() > 1) usage_error(std::string(name) + " must be a 1-D sequence of ids, got shape " + shape_text(a));
  if (a.size() > 0) require_integers(a, name);
  if (a.size() == 0) return {};
  const py::array wide = c_contiguous(a, numpy().attr("int64"));
  const auto* p = static_cast<const int64_t*>(wide.data());
  std::vector<int32_t> out(static_cast<size_t>(wide.size()));
  for (size_t i = 0; i < out.size(); ++i) {
    if (p[i] < std::numeric_limits<int32_t>::min() || p[i] > std::numeric_limits<int32_t>::max())
      usage_error(std::string(name) + "[" + std::to_string(i) + "] = " + std::to_string(p[i]) + " is not a vertex id");
    out[i] = static_cast<int32_t>(p[i]);
  }
  return out;
}

std::vector<MeshPoint> mesh_points(const py::handle& points, const char* name) {
  std::vector<MeshPoint> out;
  if (py::isinstance<py::tuple>(points) && py::len(points) == 2) {
    const py::array bary = as_array(points[py::int_(1)], name);
    if (bary.ndim() == 2) {  // (faces, bary)
      const std::vector<int32_t> faces = vertex_ids(points[py::int_(0)], name);
      if (bary.shape(1) != 3 || bary.shape(0) != static_cast<py::ssize_t>(faces.size()))
        usage_error(std::string(name) + ": (faces, bary) needs bary of shape (" + std::to_string(faces.size()) +
                    ", 3), got " + shape_text(bary));
      const py::array b = c_contiguous(bary, numpy().attr("float64"));
      const auto* w = static_cast<const double*>(b.data());
      for (size_t k = 0; k < faces.size(); ++k)
        out.push_back(MeshPoint::in_face(faces[k], w[3 * k], w[3 * k + 1], w[3 * k + 2]));
      return out;
    }
  }
  for (int32_t v : vertex_ids(points, name)) out.push_back(MeshPoint::at_vertex(v));
  return out;
}

py::tuple face_points(const std::vector<MeshPoint>& points) {
  std::vector<int32_t> faces(points.size());
  std::vector<double> bary(3 * points.size());
  for (size_t k = 0; k < points.size(); ++k) {
    faces[k] = points[k].face;
    for (int c = 0; c < 3; ++c) bary[3 * k + c] = points[k].bary[c];
  }
  const auto n = static_cast<py::ssize_t>(points.size());
  return py::make_tuple(take(std::move(faces)), take(std::move(bary), {n, 3}));
}

View<double> out_view(const py::handle& out, size_t n, const char* name) {
  if (!py::isinstance<py::array>(out)) usage_error(std::string(name) + " must be a NumPy array");
  py::array a = py::reinterpret_borrow<py::array>(out);
  if (a.dtype().kind() != 'f' || a.itemsize() != 8 || !a.dtype().attr("isnative").cast<bool>())
    usage_error(std::string(name) + " must be float64, got " + dtype_text(a));
  if (a.ndim() != 1 || static_cast<size_t>(a.shape(0)) != n)
    usage_error(std::string(name) + " must have shape (" + std::to_string(n) + ",), got " + shape_text(a));
  if (!(a.flags() & py::array::c_style) || !a.writeable())
    usage_error(std::string(name) + " must be C-contiguous and writeable");
  return View<double>(static_cast<double*>(a.mutable_data()), n);
}

py::object result(const py::dict& fields) {
  return py::module_::import("types").attr("SimpleNamespace")(**fields);
}

}  // namespace locus::python
