// ctest `public_headers_cxx17`: every installed public
// header compiles as C++17 with only the public include directories
// (core/include, io/include, engine/include), and locus::View takes what a
// C++17 host passes. Compiled with -fsyntax-only -std=c++17 -Werror; nothing
// runs. (.cc, not .cpp: the test suite globs tests/*.cpp into locus-tests.)
#include <locus/engine/geodesic_requests.hpp>
#include <locus/engine/heat_time.hpp>
#include <locus/engine/mesh_input.hpp>
#include <locus/engine/operator_choice.hpp>
#include <locus/error.hpp>
#include <locus/locus.h>
#include <locus/mesh.hpp>
#include <locus/mesh_io.hpp>
#include <locus/mesh_info.hpp>
#include <locus/mesh_view.hpp>
#include <locus/run_context.hpp>
#include <locus/session.hpp>
#include <locus/sparse_matrix.hpp>
#include <locus/version.h>
#include <locus/view.hpp>

#include <array>
#include <type_traits>
#include <vector>

static_assert(__cplusplus == 201703L, "this probe must be compiled with -std=c++17");
#ifdef LOCUS_VIEW_HAS_SPAN
#error "locus/view.hpp must not use std::span under C++17"
#endif

// What converts: a mutable container to a mutable or read-only view, a
// temporary container to a read-only view only (a mutable one would dangle),
// a mutable view to a read-only one and never the reverse.
static_assert(std::is_convertible_v<std::vector<double>&, locus::View<double>>);
static_assert(std::is_convertible_v<std::vector<double>&, locus::ConstView<double>>);
static_assert(std::is_convertible_v<const std::vector<double>&, locus::ConstView<double>>);
static_assert(!std::is_convertible_v<const std::vector<double>&, locus::View<double>>);
static_assert(std::is_convertible_v<std::vector<int32_t>&&, locus::ConstView<int32_t>>);
static_assert(!std::is_convertible_v<std::vector<double>&&, locus::View<double>>);
static_assert(std::is_convertible_v<std::array<int32_t, 3>&, locus::ConstView<int32_t>>);
static_assert(std::is_convertible_v<locus::View<double>, locus::ConstView<double>>);
static_assert(!std::is_convertible_v<locus::ConstView<double>, locus::View<double>>);
static_assert(!std::is_convertible_v<std::vector<float>&, locus::ConstView<double>>);
static_assert(!std::is_convertible_v<std::vector<int64_t>&, locus::ConstView<int32_t>>);

// The C++ API as a C++17 host calls it (never run: -fsyntax-only).
[[maybe_unused]] static double host(const locus::Session& s, locus::Mesh& m) {
  std::vector<double> out(static_cast<size_t>(s.num_vertices()));
  s.geodesic_distance(0, out);
  s.geodesic_distance(0, locus::View<double>(out.data(), out.size()));
  const std::vector<int32_t> src{0, 1};
  const int32_t tgt[] = {2, 3};
  const std::vector<double> h = s.heat_values(src, tgt);
  const std::array<int32_t, 3> tri{0, 1, 2};
  m.add_face(tri);
  double sum = 0;
  for (int32_t v : m.face(0)) sum += m.x[static_cast<size_t>(v)];
  return sum + h[0] + out[0];
}
