// locus.Session: the pipelines on the heat operator M - tL (thesis ch. 3–4):
// heat Voronoi diagrams (§3.4), natural-neighbor coordinates and skinning
// weights (§3.7.2), ADF/HKS and pairwise heat exchange (§4.6), isotropic heat
// CVT with optional remeshing (§3.7).
#include <memory>
#include <string>

#include "arrays.hpp"
#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

namespace py = pybind11;
using namespace py::literals;

namespace locus::python {
namespace {

HeatQuery heat(double t_factor, double t) {
  HeatQuery q;
  q.t_factor = t_factor;
  q.t = t;
  return q;
}

DiagonalMethod diagonal_method(const std::string& name) {
  if (name == "subset") return DiagonalMethod::Subset;
  // 'selinv': the CLI's name (`locus adf --method selinv`); the long name stays accepted.
  if (name == "selinv" || name == "selected_inversion") return DiagonalMethod::SelectedInversion;
  usage_error("method must be 'subset' or 'selinv' (selected inversion), got '" + name + "'");
}

py::object voronoi(const Session& s, const py::handle& generators, double t_factor, double t, int threads,
                   py::object progress) {
  const std::vector<MeshPoint> g = mesh_points(generators, "generators");
  VoronoiResult r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.voronoi(ConstView<MeshPoint>(g), heat(t_factor, t), ctx); });
  const auto np = static_cast<py::ssize_t>(r.points.size() / 3);
  return result(py::dict("labels"_a = take(std::move(r.label)), "points"_a = take(std::move(r.points), {np, 3}),
                         "line_offsets"_a = take(std::move(r.line_offsets)), "line_points"_a = take(std::move(r.line_points)),
                         "corners"_a = r.corners, "empty_cells"_a = r.empty_cells,
                         "vertices_without_heat"_a = r.vertices_without_heat));
}

py::object nn_result(NaturalNeighborResult&& r) {
  return result(py::dict("weights"_a = take(std::move(r.weight)), "cell_area"_a = r.cell_area, "at_site"_a = r.at_site,
                         "degenerate"_a = r.degenerate));
}

MeshPoint one_point(const py::handle& point) {
  const std::vector<MeshPoint> p = mesh_points(point, "point");
  if (p.size() != 1) usage_error("point must be one vertex id or one (face, bary) point, got " + std::to_string(p.size()));
  return p[0];
}

py::object skinning(const Session& s, const py::handle& handles, double t_factor, double t, int threads,
                    py::object progress) {
  const std::vector<MeshPoint> h = mesh_points(handles, "handles");
  SkinningWeightsResult r;
  run({threads, progress},
      [&](const RunContext& ctx) { r = s.skinning_weights(ConstView<MeshPoint>(h), heat(t_factor, t), ctx); });
  const py::ssize_t nh = r.handles;
  return result(py::dict("weights"_a = take(std::move(r.weight), {py::ssize_t(s.num_vertices()), nh}),
                         "degenerate_vertices"_a = r.degenerate_vertices, "fallback_faces"_a = r.fallback_faces,
                         "max_clamped"_a = r.max_clamped));
}

py::array hks(const Session& s, const py::handle& t_factors, const py::handle& vertices, const std::string& method,
              int threads, py::object progress) {
  const py::array tf = py::module_::import("numpy").attr("asarray")(t_factors, "dtype"_a = "float64").attr("ravel")();
  std::vector<HeatQuery> times;
  for (const py::handle x : tf) times.push_back(heat(x.cast<double>(), 0.0));
  const std::vector<int32_t> vs = vertices.is_none() ? std::vector<int32_t>{} : vertex_ids(vertices, "vertices");
  const DiagonalMethod dm = diagonal_method(method);
  std::vector<double> out;
  run({threads, progress}, [&](const RunContext& ctx) {
    out = s.heat_kernel_signature(ConstView<HeatQuery>(times), ConstView<int32_t>(vs), dm, ctx);
  });
  const py::ssize_t rows = vs.empty() ? s.num_vertices() : py::ssize_t(vs.size());
  return take(std::move(out), {rows, py::ssize_t(times.size())});
}

py::object cvt(const Session& s, int32_t sites, int32_t iterations, uint64_t seed, bool remesh, int threads,
               py::object progress) {
  CvtResult r;
  run({threads, progress}, [&](const RunContext& ctx) { r = s.cvt(sites, iterations, seed, ctx, remesh); });
  const auto ns = static_cast<py::ssize_t>(r.site_face.size());
  py::dict d("labels"_a = take(std::vector<int32_t>(r.label.begin(), r.label.end())), "sites"_a = take(std::move(r.site_xyz), {ns, 3}),
             "site_face"_a = take(std::move(r.site_face)), "site_vertex"_a = take(std::move(r.site_vertex)),
             "site_bary"_a = take(std::move(r.site_bary), {ns, 3}), "empty_cells"_a = r.empty_cells,
             "unreached"_a = r.unreached, "remeshed"_a = r.remeshed);
  if (remesh) {
    const auto nrv = static_cast<py::ssize_t>(r.remesh_xyz.size() / 3);
    const auto nrf = static_cast<py::ssize_t>(r.remesh_triangles.size() / 3);
    d["remesh_V"] = take(std::move(r.remesh_xyz), {nrv, 3});
    d["remesh_F"] = take(std::move(r.remesh_triangles), {nrf, 3});
    d["remesh_site"] = take(std::move(r.remesh_site));
    d["added_sites"] = r.added_sites;
    d["genus"] = r.remesh_genus;
    d["components"] = r.remesh_components;
    d["boundary_loops"] = r.remesh_boundary_loops;
    d["mean_min_angle_deg"] = r.mean_min_angle_deg;
    d["min_angle_deg"] = r.min_angle_deg;
    d["pct_below_30_deg"] = r.pct_below_30_deg;
    d["hausdorff_rel"] = r.hausdorff_rel;
  }
  return result(d);
}

void bind_natural_neighbors(py::module_& m, SessionClass& cls) {
  py::class_<NaturalNeighbors>(m, "NaturalNeighbors",
                               "A prepared natural-neighbor field (Session.prepare_natural_neighbors): the sites' heat "
                               "Voronoi diagram, computed once; coordinates() may run from any number of threads.")
      .def_property_readonly("num_sites", &NaturalNeighbors::num_sites)
      .def(
          "coordinates",
          [](const NaturalNeighbors& nn, const py::handle& point) {
            const MeshPoint p = one_point(point);
            NaturalNeighborResult r;
            run({}, [&](const RunContext&) { r = nn.coordinates(p); });
            return nn_result(std::move(r));
          },
          "point"_a,
          "coordinates(point) -> namespace\n\nNatural-neighbor (area-stealing) coordinates of one point (a vertex "
          "id or ([face], [[b0, b1, b2]])): .weights (one per site, >= 0, summing to 1), .cell_area, .at_site, "
          ".degenerate.");
  cls.def(
      "prepare_natural_neighbors",
      [](const Session& s, const py::handle& sites, double t_factor, double t, int threads, py::object progress) {
        const std::vector<MeshPoint> p = mesh_points(sites, "sites");
        std::unique_ptr<NaturalNeighbors> nn;
        run({threads, progress}, [&](const RunContext& ctx) {
          nn = std::make_unique<NaturalNeighbors>(s.prepare_natural_neighbors(ConstView<MeshPoint>(p), heat(t_factor, t), ctx));
        });
        return nn;
      },
      "sites"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0, "progress"_a = py::none(),
      "prepare_natural_neighbors(sites, *, t_factor=1.0, t=0.0, threads=0, progress=None) -> NaturalNeighbors\n\n"
      "The sites' heat Voronoi diagram, prepared for many coordinate queries. sites: vertex ids or (faces, bary).");
  cls.def(
      "natural_neighbor_coordinates",
      [](const Session& s, const py::handle& sites, const py::handle& point, double t_factor, double t, int threads,
         py::object progress) {
        const std::vector<MeshPoint> p = mesh_points(sites, "sites");
        const MeshPoint q = one_point(point);
        NaturalNeighborResult r;
        run({threads, progress}, [&](const RunContext& ctx) {
          r = s.natural_neighbor_coordinates(ConstView<MeshPoint>(p), q, heat(t_factor, t), ctx);
        });
        return nn_result(std::move(r));
      },
      "sites"_a, "point"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0, "progress"_a = py::none(),
      (std::string("natural_neighbor_coordinates(sites, point, *, t_factor=1.0, t=0.0, threads=0, progress=None)\n\n"
                   "One-shot natural-neighbor coordinates (thesis §3.7.2) of `point` with respect to `sites` "
                   "(see NaturalNeighbors.coordinates for the result).\n") + kCallArgs).c_str());
}

}  // namespace

void bind_session_diffusion(py::module_& m, SessionClass& cls) {
  const std::string time_doc =
      "t_factor, t: diffusion time t = t_factor * h^2 (h the mean edge length) unless the absolute t (units of "
      "length^2) is > 0. One factorization of M - tL per t serves every diffusion query.\n";
  cls.def("voronoi", &voronoi, "generators"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0,
          "progress"_a = py::none(),
          ("voronoi(generators, *, t_factor=1.0, t=0.0, threads=0, progress=None) -> namespace\n\n"
           "Heat-diffusion Voronoi diagram (thesis §3.4) of 1..nv generators (vertex ids or (faces, bary)): .labels "
           "(int32 per vertex: the generator with the most heat), .points ((k, 3) diagram points on edges and "
           "corners), polyline i = .line_points[.line_offsets[i]:.line_offsets[i+1]], .corners, .empty_cells, "
           ".vertices_without_heat.\n" + time_doc + kCallArgs).c_str());
  bind_natural_neighbors(m, cls);
  cls.def("skinning_weights", &skinning, "handles"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0,
          "progress"_a = py::none(),
          ("skinning_weights(handles, *, t_factor=1.0, t=0.0, threads=0, progress=None) -> namespace\n\n"
           "Natural-neighbor skinning weights of every vertex: .weights (float64 (nv, len(handles)), rows sum to 1), "
           ".degenerate_vertices, .fallback_faces, .max_clamped.\n" + time_doc + kCallArgs).c_str());
  cls.def(
      "auto_diffusion",
      [](const Session& s, const py::handle& vertices, double t_factor, const std::string& method, int threads,
         py::object progress) {
        py::array a = hks(s, py::make_tuple(t_factor), vertices, method, threads, progress);
        return a.attr("reshape")(-1);
      },
      "vertices"_a = py::none(), py::kw_only(), "t_factor"_a = 1.0, "method"_a = "subset", "threads"_a = 0,
      "progress"_a = py::none(),
      ("auto_diffusion(vertices=None, *, t_factor=1.0, method='subset', threads=0, progress=None) -> ndarray\n\n"
       "Auto-diffusion function (M - tL)^{-1}[v, v] (thesis §4.6) at `vertices` (None: all, in order), t = t_factor "
       "* h^2. method: 'subset' (one etree path per vertex) or 'selinv' (selected inversion, as the CLI's "
       "--method; 'selected_inversion' also accepted): all diagonal entries at once, faster for all vertices).\n" + std::string(kCallArgs)).c_str());
  cls.def("heat_kernel_signature", &hks, "t_factors"_a, "vertices"_a = py::none(), py::kw_only(), "method"_a = "subset",
          "threads"_a = 0, "progress"_a = py::none(),
          ("heat_kernel_signature(t_factors, vertices=None, *, method='subset', threads=0, progress=None) -> ndarray\n\n"
           "ADF for several times t_j = t_factors[j] * h^2: float64 (len(vertices) or nv, len(t_factors)).\n" +
           std::string(kCallArgs)).c_str());
  cls.def(
      "heat_exchange",
      [](const Session& s, const py::handle& sources, const py::handle& targets, double t_factor, double t,
         int threads, py::object progress) {
        const std::vector<int32_t> src = vertex_ids(sources, "sources"), dst = vertex_ids(targets, "targets");
        std::vector<double> out;
        run({threads, progress}, [&](const RunContext& ctx) {
          out = s.heat_exchange(ConstView<int32_t>(src), ConstView<int32_t>(dst), heat(t_factor, t), ctx);
        });
        return take(std::move(out));
      },
      "sources"_a, "targets"_a, py::kw_only(), "t_factor"_a = 1.0, "t"_a = 0.0, "threads"_a = 0,
      "progress"_a = py::none(),
      ("heat_exchange(sources, targets, *, t_factor=1.0, t=0.0, threads=0, progress=None) -> ndarray\n\n"
       "Pairwise heat exchange (thesis §4.6): unit heat at every source (repeats add), one step of M - tL; the heat "
       "at each target (float64, (len(targets),)).\n" + time_doc + kCallArgs).c_str());
  cls.def("cvt", &cvt, "sites"_a, "iterations"_a = 10, "seed"_a = 1, py::kw_only(), "remesh"_a = false, "threads"_a = 0,
          "progress"_a = py::none(),
          (std::string("cvt(sites, iterations=10, seed=1, *, remesh=False, threads=0, progress=None) -> namespace\n\n"
                       "Isotropic heat CVT (thesis §3.7): `sites` seeded random initial sites (1..nv, at least one "
                       "per connected component; more than nv with remesh=True: the cells run on a midpoint "
                       "subdivision), `iterations` localized Lloyd steps, t = 4 h^2 (as `locus cvt`).\n"
                       "Returns .labels (int32 per vertex: its cell), .sites ((k, 3) positions), .site_face, "
                       ".site_vertex, .site_bary, .empty_cells, .unreached; with remesh=True also the remeshed "
                       "surface .remesh_V ((n, 3) float64), .remesh_F ((m, 3) int32), .remesh_site and its "
                       "quality (.genus, .components, .boundary_loops, .mean_min_angle_deg, .min_angle_deg, "
                       ".pct_below_30_deg, .hausdorff_rel relative to the bounding-box diagonal).\n") +
           kCallArgs).c_str());
}

}  // namespace locus::python
