// The locus.Session class (the prepared tier), bound in
// parts by topic: session_class.cpp (construction, positions, stats,
// preparation), session_geodesic.cpp (heat method: distance, log map, heat
// values, random points), session_diffusion.cpp (Voronoi, natural neighbors,
// skinning, ADF/HKS, heat exchange, CVT), session_shape.cpp (deformation,
// parameterizations, perfect Laplacian, self-supporting surfaces).
#pragma once
#include <string>

#include <pybind11/pybind11.h>

#include "locus/session.hpp"

namespace locus::python {

using SessionClass = pybind11::class_<Session>;

void bind_session(pybind11::module_& m);
void bind_session_geodesic(SessionClass& cls);
void bind_session_commands(SessionClass& cls);  // geodesic, logmap: every CLI option
void bind_session_diffusion_commands(SessionClass& cls);  // adf, hks, heat, nncoords: every CLI option
void bind_session_param_command(SessionClass& cls);       // param: every CLI option
void bind_session_laplacian_commands(SessionClass& cls);  // perfect-laplacian, selfsupport: every CLI option
void bind_session_voronoi_command(SessionClass& cls);     // voronoi: every CLI option
void bind_session_factor_command(SessionClass& cls);      // factor: every CLI option
void bind_session_cvt_command(SessionClass& cls);         // cvt: every CLI option
void bind_session_skinweights_command(SessionClass& cls);  // skinweights: every CLI option
void bind_session_diffusion(pybind11::module_& m, SessionClass& cls);
void bind_session_shape(SessionClass& cls);

// The docstring tail every computing method shares.
inline constexpr const char* kCallArgs =
    "threads: worker threads for this call (default 0 = all cores).\n"
    "progress: None (default) or callable(fraction, phase) called as the work advances (fraction in [0, 1]); "
    "returning True cancels (locus.Cancelled). Ctrl-C cancels and raises KeyboardInterrupt.\n"
    "The GIL is released while the engine computes.";

// The heat method's t_factor argument: None = 0, the engine's default (4; 8 on polygon meshes).
// A default as Python writes it ('1h2', False, 1e-06), for the signature line a
// docstring opens with (python/locus/_signatures.py reads it; pybind11's own is off).
template <class T>
std::string py_literal(const T& value) {
  return pybind11::repr(pybind11::cast(value)).template cast<std::string>();
}

// A text argument that may be None (a file name or a time not given): "" for None, else str(x).
inline std::string optional_text(const pybind11::handle& x) {
  return x.is_none() ? std::string() : pybind11::str(x).cast<std::string>();
}

inline double heat_method_t_factor(const pybind11::handle& t_factor) {
  return t_factor.is_none() ? 0.0 : t_factor.cast<double>();
}

}  // namespace locus::python

namespace locus::python {

// Chapter-2 results as Python namespaces (shared with the polygon one-shots in mesh_functions.cpp).
pybind11::object disk_param_result(DiskParamResult&& r);
pybind11::object perfect_laplacian_result(PerfectLaplacianOutput&& r);
pybind11::object self_support_result(SelfSupportOutput&& r);
DiskParamMethod disk_param_method(const std::string& name);

}  // namespace locus::python
