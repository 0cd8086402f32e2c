// A locus::Mesh as NumPy arrays (V (nv, 3) float64; F (nf, 3) int32 for
// triangle meshes, (nf, k) int32 when every face has k corners (quads), else a
// list of int32 arrays), for read_mesh, subdivide and Session.V / .F / .polygons.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "locus/mesh.hpp"

namespace locus::python {

pybind11::array positions_array(const Mesh& m);
pybind11::object faces_object(const Mesh& m);

}  // namespace locus::python
