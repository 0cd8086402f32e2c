// Input attributes survive: a PLY with float positions,
// normals, colours and a custom property, run through geodesic, logmap and
// cvt (--labels), keeps all of them with their types next to the result.
// The input is written here by hand as ascii PLY (not by locus' writer).
#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tests/tools/cli_support.hpp"

using namespace locus::test_cli;

namespace {

// Float-exact positions, unit normals, a colour ramp and a custom quality.
std::string attributed_ply(const locus::Mesh& m) {
  std::ostringstream s;
  s.precision(9);
  const int32_t nv = m.num_vertices();
  s << "ply\nformat ascii 1.0\nelement vertex " << nv
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
       "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty double quality\nelement face "
    << m.num_faces() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int32_t v = 0; v < nv; ++v) {
    const float x = static_cast<float>(m.x[v]), y = static_cast<float>(m.y[v]), z = static_cast<float>(m.z[v]);
    s << x << ' ' << y << ' ' << z << ' ' << x << ' ' << y << ' ' << z << ' ' << (v % 256) << ' ' << (v * 7 % 256) << ' '
      << 200 << ' ' << 0.25 * v << '\n';
  }
  for (int32_t f = 0; f < m.num_faces(); ++f) s << "3 " << m.f0[f] << ' ' << m.f1[f] << ' ' << m.f2[f] << '\n';
  return s.str();
}

void check_carried(const std::string& path, const std::string& result_name, int32_t nv) {
  CAPTURE(path);
  locus::MeshAttributes a;
  const locus::Mesh back = locus::read_mesh(path, {}, &a);
  REQUIRE(back.num_vertices() == nv);
  CHECK(a.float_positions);
  auto find = [&](const std::string& name) -> const locus::VertexProperty* {
    for (const auto& p : a.vertex)
      if (p.name == name) return &p;
    return nullptr;
  };
  using T = locus::VertexProperty::Type;
  for (const char* n : {"nx", "ny", "nz"}) {
    const auto* p = find(n);
    REQUIRE(p);
    CHECK(p->type == T::Float);
  }
  CHECK(find("nx")->values[5] == static_cast<double>(static_cast<float>(back.x[5])));
  for (const char* n : {"red", "green", "blue"}) {
    const auto* p = find(n);
    REQUIRE(p);
    CHECK(p->type == T::UInt8);
  }
  CHECK(find("green")->values[3] == 21);
  const auto* q = find("quality");
  REQUIRE(q);
  CHECK(q->type == T::Double);
  CHECK(q->values[10] == 2.5);
  CHECK(find(result_name) != nullptr);
}

}  // namespace

TEST_CASE("attributes: normals, colours and a custom PLY property survive geodesic, logmap and cvt") {
  if (!have_locus()) return;
  Scratch dir("attrs");
  const locus::Mesh sphere = locus::make_icosphere(3);
  const std::string in = dir / "in.ply";
  std::ofstream(in) << attributed_ply(sphere);
  const int32_t nv = sphere.num_vertices();
  REQUIRE(run_locus(dir, {"geodesic", in, "--source", "0", "-o", dir / "g.ply"}).status == 0);
  check_carried(dir / "g.ply", "distance", nv);
  REQUIRE(run_locus(dir, {"logmap", in, "--center", "0", "--fraction", "0.2", "-o", dir / "l.ply"}).status == 0);
  check_carried(dir / "l.ply", "angle", nv);
  REQUIRE(run_locus(dir, {"cvt", in, "--sites", "30", "--iters", "3", "--labels", dir / "c.ply", "-o", dir / "r.obj"})
              .status == 0);
  check_carried(dir / "c.ply", "label", nv);
}
