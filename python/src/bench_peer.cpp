// locus._locus._bench: the C++ peer of tools/bench_python.py (the binding's
// overhead per query against the same query in C++, in the same process). Not part of the API.
#include <chrono>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "locus/session.hpp"

namespace py = pybind11;

namespace locus::python {

void bind_bench_peer(py::module_& m) {
  py::module_ b = m.def_submodule("_bench", "benchmark peers (tools/bench_python.py); not part of the API");
  b.def(
      "geodesic_seconds",
      [](const Session& s, const std::vector<int32_t>& sources, int repeats) {
        // Seconds per call of Session::geodesic_distance(source, out) into one
        // preallocated array, as a C++ host would call it.
        std::vector<double> seconds, out(static_cast<size_t>(s.num_vertices()));
        py::gil_scoped_release release;
        for (int r = 0; r < repeats; ++r)
          for (int32_t v : sources) {
            const auto t0 = std::chrono::steady_clock::now();
            s.geodesic_distance(v, View<double>(out));
            seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
          }
        return seconds;
      },
      py::arg("session"), py::arg("sources"), py::arg("repeats") = 1);
}

}  // namespace locus::python
