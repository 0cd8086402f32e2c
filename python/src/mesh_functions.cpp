// Module-level functions that need no Session: mesh files,
// midpoint subdivision, the engine's PNG preview, and the chapter-2 one-shots
// on polygon meshes (a Session takes them too; these have nothing to cache).
#include <string>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "mesh_arrays_out.hpp"
#include "session_bindings.hpp"

#include "locus/io/write_png.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/render/rasterize.hpp"
#include "locus/mesh_io.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

py::tuple read(const std::string& path, bool weld) {
  Mesh m;
  {
    ReadOptions ro;
    ro.weld = weld;
    py::gil_scoped_release release;
    m = read_mesh(path, ro);
  }
  return py::make_tuple(positions_array(m), faces_object(m));
}

void write(const std::string& path, const py::handle& V, const py::handle& F, const py::dict& properties) {
  const Mesh m = polygon_mesh(V, F);
  WriteOptions wo;
  for (const auto& [name, values] : properties) {
    VertexProperty p;
    p.name = py::str(name).cast<std::string>();
    const py::array a = py::module_::import("numpy").attr("asarray")(values, "dtype"_a = "float64").attr("ravel")();
    if (a.size() != m.num_vertices())
      usage_error("property '" + p.name + "' has " + std::to_string(a.size()) + " values, expected one per vertex (" +
                  std::to_string(m.num_vertices()) + ")");
    const auto* d = static_cast<const double*>(a.data());
    p.values.assign(d, d + a.size());
    wo.vertex_properties.push_back(std::move(p));
  }
  py::gil_scoped_release release;
  write_mesh(path, m, wo);
}

py::tuple subdivide(const py::handle& V, const py::handle& F, int times) {
  if (times < 0) usage_error("times must be >= 0, got " + std::to_string(times));
  const Mesh in = polygon_mesh(V, F);
  Mesh out;
  {
    py::gil_scoped_release release;
    out = subdivide_midpoint(in, times);
  }
  return py::make_tuple(positions_array(out), faces_object(out));
}

Coloring coloring_of(const std::string& name) {
  if (name == "scalar") return Coloring::Scalar;
  if (name == "labels") return Coloring::Labels;
  if (name == "checker") return Coloring::Checker;
  usage_error("coloring must be 'scalar', 'labels' or 'checker', got '" + name + "'");
}

// (k, 3) float64 points, or none.
std::vector<Vec3d> points3(const py::handle& p, const char* what) {
  std::vector<Vec3d> out;
  if (p.is_none()) return out;
  const py::array a = py::module_::import("numpy").attr("asarray")(p, "dtype"_a = "float64");
  if (a.size() % 3 != 0 || (a.ndim() != 1 && (a.ndim() != 2 || a.shape(1) != 3)))
    throw py::value_error(std::string(what) + ": expected points of shape (k, 3)");
  const py::array c = py::module_::import("numpy").attr("ascontiguousarray")(a).attr("ravel")();
  const auto* d = static_cast<const double*>(c.data());
  for (py::ssize_t i = 0; i + 2 < c.size(); i += 3) out.push_back(Vec3d{d[i], d[i + 1], d[i + 2]});
  return out;
}

py::array render(const py::handle& V, const py::handle& F, const py::handle& values, const std::string& coloring,
                 bool edges, int width, int height, const std::string& path, const std::string& title,
                 const py::handle& markers, const std::string& marker_label, const py::handle& view) {
  const Mesh m = polygon_mesh(V, F);
  RasterOptions ro;
  ro.width = width;
  ro.height = height;
  ro.edges = edges;
  ro.title = title;
  ro.markers = points3(markers, "markers");
  ro.marker_label = marker_label;
  if (!view.is_none()) {
    const std::vector<Vec3d> v = points3(view, "view");
    if (v.size() != 1 || (v[0][0] == 0 && v[0][1] == 0 && v[0][2] == 0))
      throw py::value_error("view: expected one direction (x, y, z), not all zero");
    ro.view = v[0];
  }
  std::vector<double> v;
  if (values.is_none()) {
    ro.coloring = Coloring::Labels;  // one colour: the shape (and with edges its triangles)
    v.assign(static_cast<size_t>(m.num_vertices()), 0.0);
  } else {
    ro.coloring = coloring_of(coloring);
    const py::array a = py::module_::import("numpy").attr("asarray")(values, "dtype"_a = "float64").attr("ravel")();
    const auto* d = static_cast<const double*>(a.data());
    v.assign(d, d + a.size());
  }
  RasterImage img;
  {
    py::gil_scoped_release release;
    img = rasterize_mesh(m, v, ro);
    if (!path.empty()) write_png(path, img.width, img.height, img.rgb);
  }
  return take(std::move(img.rgb), {py::ssize_t(img.height), py::ssize_t(img.width), 3});
}

void bind_polygon_one_shots(py::module_& m) {
  m.def(
      "parameterize_disk",
      [](const py::handle& V, const py::handle& F, const std::string& method, int32_t max_iterations, double eps,
         int threads, py::object progress) {
        const Mesh mesh = polygon_mesh(V, F);
        DiskParamRequest req{disk_param_method(method), max_iterations, eps};
        DiskParamResult r;
        run({threads, progress}, [&](const RunContext& ctx) { r = parameterize_disk_of(mesh, req, ctx); });
        return disk_param_result(std::move(r));
      },
      "V"_a, "F"_a, py::kw_only(), "method"_a = "perfect", "max_iterations"_a = 1000, "eps"_a = 1e-6, "threads"_a = 0,
      "progress"_a = py::none(),
      (std::string("parameterize_disk(V, F, *, method='perfect', max_iterations=1000, eps=1e-6, threads=0, "
                   "progress=None)\n\nFlip-free disk parameterization (thesis §2.6) of a polygon mesh (F: (m, k) "
                   "array, list of faces or (offsets, indices)); see Session.parameterize_disk.\n") + kCallArgs).c_str());
  m.def(
      "perfect_laplacian",
      [](const py::handle& V, const py::handle& F, bool planar, int32_t max_iterations, double eps, bool newton,
         int threads, py::object progress) {
        const Mesh mesh = polygon_mesh(V, F);
        PerfectLaplacianRequest req{planar, max_iterations, eps, newton};
        PerfectLaplacianOutput r;
        run({threads, progress}, [&](const RunContext& ctx) { r = perfect_laplacian_of(mesh, req, ctx); });
        return perfect_laplacian_result(std::move(r));
      },
      "V"_a, "F"_a, py::kw_only(), "planar"_a = false, "max_iterations"_a = 1000, "eps"_a = 1e-6, "newton"_a = true,
      "threads"_a = 0, "progress"_a = py::none(),
      (std::string("perfect_laplacian(V, F, *, planar=False, max_iterations=1000, eps=1e-6, newton=True, threads=0, "
                   "progress=None)\n\nAlgorithm 1 of thesis ch. 2 on a polygon mesh; see Session.perfect_laplacian.\n") +
       kCallArgs).c_str());
  m.def(
      "self_supporting",
      [](const py::handle& V, const py::handle& F, double load_density, int32_t max_iterations, double eps, int threads,
         py::object progress) {
        const Mesh mesh = polygon_mesh(V, F);
        SelfSupportRequest req{load_density, max_iterations, eps};
        SelfSupportOutput r;
        run({threads, progress}, [&](const RunContext& ctx) { r = self_supporting_of(mesh, req, ctx); });
        return self_support_result(std::move(r));
      },
      "V"_a, "F"_a, py::kw_only(), "load_density"_a = 1.0, "max_iterations"_a = 1000, "eps"_a = 1e-6, "threads"_a = 0,
      "progress"_a = py::none(),
      (std::string("self_supporting(V, F, *, load_density=1.0, max_iterations=1000, eps=1e-6, threads=0, "
                   "progress=None)\n\nSelf-supporting surface (thesis §2.6) of a polygon mesh; see "
                   "Session.self_supporting.\n") + kCallArgs).c_str());
}

}  // namespace

void bind_mesh_functions(py::module_& m) {
  m.def("read_mesh", &read, "path"_a, py::kw_only(), "weld"_a = true,
        "read_mesh(path, *, weld=True) -> (V, F)\n\nReads .obj, .off or .ply, and through assimp glTF (.gltf, .glb), "
        "FBX, Collada, STL, 3MF and the other asset formats (the scene flattened with its node transforms, its "
        "vertices welded by position unless weld=False): V (nv, 3) float64; F (nf, 3) int32 for triangle "
        "meshes, (nf, k) int32 when every face has k corners (quads), else a list of int32 arrays (one per "
        "polygon). InputError names the file and line of a "
        "malformed file.");
  m.def("write_mesh", &write, "path"_a, "V"_a, "F"_a, "properties"_a = py::dict(),
        "write_mesh(path, V, F, properties={})\n\nWrites .obj, .off or .ply (format from the extension; PLY binary) "
        "with optional per-vertex float64 properties {name: (nv,) array}. A failed write leaves an existing file "
        "untouched.");
  m.def("subdivide", &subdivide, "V"_a, "F"_a, "times"_a = 1,
        "subdivide(V, F, times=1) -> (V, F)\n\n1:4 midpoint subdivision `times` times (as `locus --subdivide`): "
        "each time, 4x the triangles.");
  m.def("render_preview", &render, "V"_a, "F"_a, "values"_a = py::none(), py::kw_only(), "coloring"_a = "scalar",
        "edges"_a = false, "width"_a = 800, "height"_a = 800, "path"_a = "", "title"_a = "",
        "markers"_a = py::none(), "marker_label"_a = "", "view"_a = py::none(),
        "render_preview(V, F, values=None, *, coloring='scalar', edges=False, width=800, height=800, path='', "
        "title='', markers=None, marker_label='', view=None)\n\n"
        "The engine's software-rendered preview (the CLI's --preview): an orthographic view from the mesh's "
        "principal axes (or from the side `view` = (x, y, z)), Lambert-shaded, as a (height, width, 3) uint8 image; "
        "written as PNG when path is given. title: the legend strip's quantity ('' = no legend); markers: (k, 3) "
        "points drawn as dots (sources, centres, sites), named marker_label in the legend.\n"
        "values: None (one colour) or per vertex: coloring 'scalar' (nv values, iso-bands; NaN grey), 'labels' (nv "
        "integer labels, one colour each) or 'checker' (2 nv values u, v interleaved). edges: draw the triangle "
        "edges dark (remesh previews). width, height: pixels (1..16384).");
  bind_polygon_one_shots(m);
}

}  // namespace locus::python
