// locus.Session (the prepared tier): one triangle mesh and
// every factorization derived from it, kept between calls (engine/include/
// locus/session.hpp). Construction, positions, counters and eager preparation;
// the queries are bound in session_geodesic/diffusion/shape.cpp.
#include <memory>
#include <string>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "mesh_arrays_out.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

// Triangles: an (m, 3) array (read in place through a MeshView when its
// layout allows). Polygons: (offsets, indices), a list of faces or an (m, k)
// array with k != 3 (arrays.hpp); the Session triangulates them.
bool triangle_array(const py::handle& F) {
  if (py::isinstance<py::tuple>(F) && py::len(F) == 2) return false;  // (offsets, indices)
  if (py::isinstance<py::list>(F)) {  // a list of faces: triangles when every face has 3 ids
    for (const py::handle f : F)
      if (!py::hasattr(f, "__len__") || py::len(f) != 3) return false;
    return true;
  }
  const py::array a = py::array::ensure(F);
  return !a || a.ndim() != 2 || a.shape(1) == 3;  // anything else: the triangle path's message
}

// The arrays are the mesh's content, so whatever is wrong with them is an
// InputError, also what mesh_from_view calls a usage error (a vertex id out of range).
SessionOptions session_options(const std::string& mesh_operator) {
  SessionOptions so;
  try {
    so.mesh_operator = parse_operator_choice(mesh_operator);
  } catch (const Error& e) {
    usage_error(e.what());
  }
  return so;
}

std::unique_ptr<Session> session_from_arrays(const py::handle& V, const py::handle& F, const std::string& op) {
  std::unique_ptr<Session> s;
  const SessionOptions so = session_options(op);
  if (!triangle_array(F)) {
    Mesh m = polygon_mesh(V, F);
    py::gil_scoped_release release;
    return std::make_unique<Session>(std::move(m), so);
  }
  TriangleArrays t = triangle_arrays(V, F);
  try {
    py::gil_scoped_release release;
    s = std::make_unique<Session>(t.view, so);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::BadUsage) throw Error(ErrorCode::BadInput, e.what(), e.where());
    throw;
  }
  return s;
}

py::dict operator_dict(const Session& s) {
  const OperatorReport r = s.operator_report();
  return py::dict("used"_a = r.used(), "asked"_a = operator_choice_name(r.asked), "reason"_a = r.reason(),
                  "non_manifold_edges"_a = r.non_manifold_edges, "non_manifold_vertices"_a = r.non_manifold_vertices,
                  "zero_area_faces"_a = r.zero_area_faces, "needle_faces"_a = r.needle_faces,
                  "inconsistent_orientation_edges"_a = r.inconsistent_orientation_edges,
                  "unreferenced_vertices"_a = r.unreferenced_vertices);
}

// The mesh report as `locus info --json` gives it (the same keys; genus None when undefined).
py::dict info_dict(const Session& s) {
  const MeshInfo r = s.info();
  py::dict hist;
  for (size_t d = 0; d < r.face_degree_histogram.size(); ++d)
    if (r.face_degree_histogram[d] != 0) hist[py::str(std::to_string(d))] = r.face_degree_histogram[d];
  py::dict bbox("min"_a = py::make_tuple(r.bbox_min[0], r.bbox_min[1], r.bbox_min[2]),
                "max"_a = py::make_tuple(r.bbox_max[0], r.bbox_max[1], r.bbox_max[2]));
  return py::dict("n_vertices"_a = r.n_vertices, "n_faces"_a = r.n_faces, "n_edges"_a = r.n_edges,
                  "face_degree_histogram"_a = hist, "components"_a = r.components,
                  "boundary_loops"_a = r.boundary_loops, "euler_characteristic"_a = r.euler_characteristic,
                  "genus"_a = r.genus >= 0 ? py::object(py::int_(r.genus)) : py::object(py::none()),
                  "manifold"_a = r.manifold, "non_manifold_edges"_a = r.non_manifold_edges,
                  "non_manifold_vertices"_a = r.non_manifold_vertices, "degenerate_faces"_a = r.degenerate_faces,
                  "unreferenced_vertices"_a = r.unreferenced_vertices, "bbox"_a = bbox,
                  "mean_edge_length"_a = r.mean_edge_length);
}

py::dict stats(const Session& s) {
  const SessionStats st = s.stats();
  return py::dict("symbolic_analyses"_a = st.symbolic_analyses, "numeric_factorizations"_a = st.numeric_factorizations,
                  "heat_engines"_a = st.heat_engines, "deform_operators"_a = st.deform_operators,
                  "positions_version"_a = st.positions_version);
}

HeatQuery heat(double t_factor, double t) {
  HeatQuery q;
  q.t_factor = t_factor;
  q.t = t;
  return q;
}

// The Session's read-only views of its mesh and of what it chose.
void bind_session_state(SessionClass& cls) {
  cls.def_property_readonly("operator", &operator_dict,
                            "The Laplacian the Session runs on: dict(used='cotan'|'robust', asked, reason, and the "
                            "defect counts that made 'auto' choose the robust one).");
  cls.def("info", &info_dict,
          "info() -> dict\n\nSizes, topology and defects of the mesh as given, as `locus info --json` reports them: n_vertices, "
          "n_faces, n_edges, face_degree_histogram, components, boundary_loops, euler_characteristic, genus (None "
          "unless a connected manifold), manifold, non_manifold_edges, non_manifold_vertices, degenerate_faces, "
          "unreferenced_vertices, bbox (min, max), mean_edge_length.");
  cls.def_property_readonly("num_vertices", &Session::num_vertices);
  cls.def_property_readonly("num_faces", &Session::num_faces, "Triangles (of the triangulation for a polygon mesh).");
  cls.def_property_readonly("has_polygons", &Session::has_polygons, "Whether F had a face of more than 3 corners.");
  cls.def_property_readonly("num_polygons", &Session::num_polygons, "Faces as given (num_faces for triangles).");
  cls.def_property_readonly("polygons", [](const Session& s) { return faces_object(s.polygons()); },
                            "A copy of the faces as given: (nf, k) int32 when every face has k corners (3 for "
                            "triangles), else a list of int32 arrays.");
  cls.def_property_readonly("triangle_polygon", [](const Session& s) { return take(s.triangle_polygon()); },
                            "Per triangle of F, the face (as given) it belongs to: (num_faces,) int32.");
  cls.def_property_readonly("num_edges", &Session::num_edges, "Unique edges of the triangles; of the faces as given for a polygon mesh (the edges of perfect_laplacian and self_supporting).");
  cls.def_property_readonly("mean_edge_length", &Session::mean_edge_length,
                            "h, the mean edge length of the current positions (units of the positions).");
  cls.def_property_readonly("V", [](const Session& s) { return positions_array(s.mesh()); },
                            "A copy of the current positions, (nv, 3) float64.");
  cls.def_property_readonly("F", [](const Session& s) { return faces_object(s.mesh()); },
                            "A copy of the triangles, (nf, 3) int32 (a polygon mesh's triangulation).");
}

// Positions, counters and the explicit factorizations (before handing a Session to threads).
void bind_session_preparation(SessionClass& cls) {
  cls.def(
      "set_positions",
      [](Session& s, const py::handle& V) {
        const std::vector<double> xyz = positions_xyz(V, s.num_vertices(), "V");
        py::gil_scoped_release release;
        s.set_positions(ConstView<double>(xyz));
      },
      "V"_a,
      "set_positions(V)\n\nNew positions ((nv, 3) float32/float64), same connectivity. Checks finiteness and that "
      "no face becomes degenerate (InputError; the old positions stay). Drops every cached numeric factor and "
      "keeps the symbolic ones (orderings depend on the connectivity only).");
  cls.def("stats", &stats,
          "stats() -> dict\n\nCounters of work done: symbolic_analyses, numeric_factorizations (diffusion "
          "operators), heat_engines (geodesic/log-map engines; each factors 2 operators), deform_operators, "
          "positions_version (set_positions calls).");
  cls.def(
      "prepare_heat",
      [](const Session& s, const py::handle& t_factor, int threads, py::object progress) {
        const double tf = heat_method_t_factor(t_factor);
        run({threads, progress}, [&](const RunContext& ctx) { s.prepare_heat(heat(tf, 0.0), ctx); });
      },
      py::kw_only(), "t_factor"_a = py::none(), "threads"_a = 0, "progress"_a = py::none(),
      (std::string("prepare_heat(*, t_factor=None, threads=0, progress=None)\n\nFactors the heat method's operators "
                   "(geodesic_distance, logmap) for t_factor now (None: 4, 8 on polygon meshes), e.g. before "
                   "handing the Session to threads.\n") +
       kCallArgs).c_str());
  cls.def(
      "prepare_diffusion",
      [](const Session& s, double t_factor, double t, int threads, py::object progress) {
        run({threads, progress}, [&](const RunContext& ctx) { s.prepare_diffusion(heat(t_factor, t), ctx); });
      },
      py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0, "progress"_a = py::none(),
      (std::string("prepare_diffusion(*, t_factor=1.0, t=0.0, threads=0, progress=None)\n\nFactors M - tL now "
                   "(Voronoi, natural neighbors, skinning, ADF/HKS, heat exchange, heat values).\n") + kCallArgs).c_str());
  cls.def(
      "prepare_patch_parameterization",
      [](const Session& s, int threads, py::object progress) {
        run({threads, progress}, [&](const RunContext& ctx) { s.prepare_patch_parameterization(ctx); });
      },
      py::kw_only(), "threads"_a = 0, "progress"_a = py::none(),
      (std::string("prepare_patch_parameterization(*, threads=0, progress=None)\n\nFactors -L + eps M now "
                   "(parameterize_patch).\n") + kCallArgs).c_str());
}

}  // namespace

void bind_session(py::module_& m) {
  SessionClass cls(m, "Session",
                   "Session(V, F, *, operator='auto')\n\n"
                   "One mesh and everything derived from it, kept between calls: the first query of a "
                   "kind factors its operator, later ones reuse the factor (stats() counts the factorizations).\n"
                   "V: (nv, 3) float32 or float64 positions; F: (nf, 3) int32, int64, uint32 or uint16 vertex ids "
                   "(0-based). Any layout; rows with adjacent x, y, z are read in place, others converted once. "
                   "Polygon meshes (quads, mixed, n-gons): F as an (nf, k) array, a list of faces (each a sequence "
                   "of ids) or (offsets, indices) in CSR form (face f = indices[offsets[f]:offsets[f + 1]]). "
                   "The Session triangulates them once (ear clipping), keeping the vertices, so per-vertex results "
                   "index V; geodesic_distance and logmap run on the polygons themselves as `locus geodesic` / "
                   "`locus logmap` do (polygon heat method, full solves, default t_factor 8; the same numbers), "
                   "parameterize_disk, perfect_laplacian and self_supporting on the polygons too, every other "
                   "method on the triangulation (face ids of surface points and results are its triangles: .F; "
                   ".triangle_polygon maps them to the faces given).\n"
                   "operator: 'auto' (default: the cotan Laplacian on a clean manifold mesh, the robust one -- "
                   "intrinsic Delaunay triangulation of the tufted cover -- when the mesh has non-manifold edges or "
                   "vertices, zero-area or needle faces, inconsistent orientation or unreferenced vertices), 'cotan' "
                   "or 'robust', as the CLI's --operator; .operator says which and why. On the robust operator "
                   "unreferenced vertices get NaN distances and logmap refuses.\n"
                   "The mesh is checked once: finite positions, ids in range, simple polygons; with operator='cotan' "
                   "also manifold, no zero-area faces, no unreferenced vertices (locus.InputError naming the first "
                   "offender).\n"
                   "Thread safety: every method may run concurrently from any number of Python threads (the GIL "
                   "is released while computing); results are bit-identical to a query run alone. "
                   "set_positions() may run concurrently with queries: queries already started finish on the old "
                   "positions.");
  cls.def(py::init(&session_from_arrays), "V"_a, "F"_a, py::kw_only(), "operator"_a = "auto");
  cls.def_static(
      "from_file",
      [](const std::string& path, const std::string& op, bool weld) {
        const SessionOptions so = session_options(op);
        ReadOptions ro;
        ro.weld = weld;
        py::gil_scoped_release release;
        return std::make_unique<Session>(Session::from_file(path, ro, so));
      },
      "path"_a, py::kw_only(), "operator"_a = "auto", "weld"_a = true,
      "Session.from_file(path, *, operator='auto', weld=True)\n\nA Session on a mesh file (.obj, .off, .ply; "
      "glTF, FBX, Collada, STL, 3MF and the other formats assimp reads, their vertices welded by position unless "
      "weld=False; triangles or polygons).");
  bind_session_state(cls);
  bind_session_preparation(cls);
  cls.def("__repr__", [](const Session& s) {
    return "<locus.Session " + std::to_string(s.num_vertices()) + " vertices, " +
           (s.has_polygons() ? std::to_string(s.num_polygons()) + " polygons as " : std::string()) +
           std::to_string(s.num_faces()) + " triangles>";
  });
  bind_session_geodesic(cls);
  bind_session_commands(cls);
  bind_session_diffusion_commands(cls);
  bind_session_param_command(cls);
  bind_session_laplacian_commands(cls);
  bind_session_voronoi_command(cls);
  bind_session_factor_command(cls);
  bind_session_cvt_command(cls);
  bind_session_skinweights_command(cls);
  bind_session_diffusion(m, cls);
  bind_session_shape(cls);
}

}  // namespace locus::python
