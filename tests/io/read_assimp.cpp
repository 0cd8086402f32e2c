// Tests for io/src/read_assimp.cpp, flatten_scene.cpp and weld_vertices.cpp:
// glTF (text with an embedded or external buffer, binary), Collada and STL
// files written here by hand, read back against the numbers written into
// them (node transforms applied by hand in the test), welding of a cube
// exported with split normals, and hostile files. When Debian's
// assimp-testmodels package is installed, a few real exports too.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io_test_support.hpp"
#include "locus/mesh_io.hpp"

using locus_test::Caught;
using locus_test::catch_error;
using locus_test::put;

namespace {

namespace fs = std::filesystem;

std::string base64(const std::string& bytes) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
    for (int k = 3; k >= 0; --k) out += t[(v >> (6 * k)) & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    out += t[(v >> 18) & 63], out += t[(v >> 12) & 63], out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8;
    out += t[(v >> 18) & 63], out += t[(v >> 12) & 63], out += t[(v >> 6) & 63], out += '=';
  }
  return out;
}

// One glTF mesh (positions + uint16 triangle indices) and the node list that places it.
struct Gltf {
  std::vector<float> pos;        // 3 per vertex
  std::vector<uint16_t> index;   // 3 per triangle
  std::string nodes = R"([{"mesh":0}])";
  std::string scene_nodes = "[0]";
  std::string extra_primitive;   // appended to the primitive list (e.g. points)
  std::string index_count;       // overrides the index accessor's count ("" = the truth)

  std::string buffer() const {
    std::string b;
    for (float f : pos) put(b, f, false);
    for (uint16_t i : index) put(b, i, false);
    while (b.size() % 4) b += '\0';
    return b;
  }
  // `uri`: "" for a .glb's BIN chunk, else the buffer's uri.
  std::string json(const std::string& uri, uint64_t byte_length) const {
    const size_t pbytes = pos.size() * 4, ibytes = index.size() * 2;
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (size_t i = 0; i < pos.size(); ++i) lo[i % 3] = std::min(lo[i % 3], pos[i]), hi[i % 3] = std::max(hi[i % 3], pos[i]);
    auto v3 = [](const float* a) {
      std::string r = "[";
      for (int k = 0; k < 3; ++k) r.append(k ? "," : "").append(std::to_string(a[k]));
      return r + "]";
    };
    std::string s = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":)" + scene_nodes + "}],";
    s += "\"nodes\":" + nodes + ",";
    s += R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4})" + extra_primitive + "]}],";
    s += "\"buffers\":[{\"byteLength\":" + std::to_string(byte_length);
    if (!uri.empty()) s += ",\"uri\":\"" + uri + "\"";
    s += "}],";
    s += R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" + std::to_string(pbytes) +
         R"(},{"buffer":0,"byteOffset":)" + std::to_string(pbytes) + ",\"byteLength\":" + std::to_string(ibytes) + "}],";
    s += R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" + std::to_string(pos.size() / 3) +
         R"(,"type":"VEC3","min":)" + v3(lo) + ",\"max\":" + v3(hi) + "},";
    s += R"({"bufferView":1,"componentType":5123,"count":)" +
         (index_count.empty() ? std::to_string(index.size()) : index_count) + R"(,"type":"SCALAR"}]})";
    return s;
  }
  std::string gltf() const {
    const std::string b = buffer();
    return json("data:application/octet-stream;base64," + base64(b), b.size());
  }
  std::string glb() const {
    std::string j = json("", buffer().size());
    while (j.size() % 4) j += ' ';
    const std::string b = buffer();
    std::string s = "glTF";
    put(s, uint32_t(2), false);
    put(s, uint32_t(12 + 8 + j.size() + 8 + b.size()), false);
    put(s, uint32_t(j.size()), false);
    s += "JSON" + j;
    put(s, uint32_t(b.size()), false);
    s += std::string("BIN\0", 4) + b;
    return s;
  }
};

// The unit square z = 0 as two triangles.
Gltf square() {
  Gltf g;
  g.pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  g.index = {0, 1, 2, 0, 2, 3};
  return g;
}

// The unit cube as an exporter with per-face normals writes it: 4 vertices
// per face (24), 12 outward triangles.
Gltf split_cube() {
  Gltf g;
  for (int a = 0; a < 3; ++a) {
    for (int s = 0; s < 2; ++s) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      const uint16_t b = uint16_t(g.pos.size() / 3);
      for (int c = 0; c < 4; ++c) {
        float p[3] = {0, 0, 0};
        p[a] = float(s);
        p[u] = (c == 1 || c == 2) ? 1.f : 0.f;
        p[v] = (c == 2 || c == 3) ? 1.f : 0.f;
        g.pos.insert(g.pos.end(), p, p + 3);
      }
      if (s == 1) g.index.insert(g.index.end(), {b, uint16_t(b + 1), uint16_t(b + 2), b, uint16_t(b + 2), uint16_t(b + 3)});
      else g.index.insert(g.index.end(), {b, uint16_t(b + 2), uint16_t(b + 1), b, uint16_t(b + 3), uint16_t(b + 2)});
    }
  }
  return g;
}

locus::Mesh from_memory(const std::string& bytes, const std::string& fmt, const locus::ReadOptions& opt = {},
                        locus::MeshAttributes* attr = nullptr) {
  return locus::read_mesh_from_memory(bytes.data(), bytes.size(), fmt, "t." + fmt, opt, attr);
}

Caught memory_error(const std::string& bytes, const std::string& fmt) {
  return catch_error([&] { from_memory(bytes, fmt); });
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const fs::path p = locus_test::scratch_dir() / "assimp" / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

// Signed volume enclosed by the triangles (divergence theorem): 1 for the
// outward unit cube, whatever the vertex numbering.
double volume(const locus::Mesh& m) {
  double v = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face(f);
    const size_t a = size_t(c[0]), b = size_t(c[1]), d = size_t(c[2]);
    v += (m.x[a] * (m.y[b] * m.z[d] - m.z[b] * m.y[d]) - m.y[a] * (m.x[b] * m.z[d] - m.z[b] * m.x[d]) +
          m.z[a] * (m.x[b] * m.y[d] - m.y[b] * m.x[d])) / 6.0;
  }
  return v;
}

// The file's square vertices placed by p -> s * R p + t (R: rotation about z by 90 degrees when `rot`).
void check_square_placed(const locus::Mesh& m, double s, bool rot, std::array<double, 3> t) {
  REQUIRE(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 2);
  CHECK(m.is_triangle_mesh());
  const double px[4] = {0, 1, 1, 0}, py[4] = {0, 0, 1, 1};
  for (int i = 0; i < 4; ++i) {
    const double x = rot ? -py[i] : px[i], y = rot ? px[i] : py[i];
    CHECK(m.x[size_t(i)] == doctest::Approx(s * x + t[0]).epsilon(1e-12));
    CHECK(m.y[size_t(i)] == doctest::Approx(s * y + t[1]).epsilon(1e-12));
    CHECK(m.z[size_t(i)] == doctest::Approx(t[2]).epsilon(1e-12));
  }
  CHECK(std::vector<int32_t>(m.face(0).begin(), m.face(0).end()) == std::vector<int32_t>{0, 1, 2});
  CHECK(std::vector<int32_t>(m.face(1).begin(), m.face(1).end()) == std::vector<int32_t>{0, 2, 3});
}

void check_bad(const Caught& e, std::initializer_list<const char*> words) {
  CHECK(e.thrown);
  CHECK(e.code == locus::ErrorCode::BadInput);
  for (const char* w : words) CHECK_MESSAGE(e.has(w), "message '" << e.message << "' lacks '" << std::string(w) << "'");
  if (std::getenv("LOCUS_SHOW_MESSAGES")) MESSAGE(e.message);
}

// Captures what the process writes to fds 1 and 2 while `f` runs.
template <class F>
std::string captured_output(F&& f) {
  const std::string path = (locus_test::scratch_dir() / "assimp_stdio.txt").string();
  std::fflush(stdout), std::fflush(stderr);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  const int out = ::dup(1), err = ::dup(2);
  ::dup2(fd, 1), ::dup2(fd, 2);
  f();
  std::fflush(stdout), std::fflush(stderr);
  ::dup2(out, 1), ::dup2(err, 2);
  ::close(out), ::close(err), ::close(fd);
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("assimp: glTF with an embedded buffer, text and binary, node transforms applied") {
  Gltf g = square();
  // Parent translated, child scaled: global = T * S, so p -> 2 p + (10, 20, 30).
  g.nodes = R"([{"children":[1],"translation":[10,20,30]},{"mesh":0,"scale":[2,2,2]}])";
  check_square_placed(from_memory(g.gltf(), "gltf"), 2, false, {10, 20, 30});
  check_square_placed(from_memory(g.glb(), "glb"), 2, false, {10, 20, 30});
  // A column-major matrix: rotation about z by 90 degrees, then (1, 2, 3).
  g.nodes = R"([{"mesh":0,"matrix":[0,1,0,0, -1,0,0,0, 0,0,1,0, 1,2,3,1]}])";
  check_square_placed(from_memory(g.glb(), "glb"), 1, true, {1, 2, 3});
  // The same file from disk, upper-case extension.
  const std::string path = write_file("square.GLB", g.glb());
  locus::MeshAttributes attr;
  const locus::Mesh m = locus::read_mesh(path, {}, &attr);
  check_square_placed(m, 1, true, {1, 2, 3});
  CHECK(m.source == path);
  CHECK(attr.asset);
  CHECK(attr.asset_report.format.find("glTF") != std::string::npos);
  CHECK(attr.asset_report.mesh_instances == 1);
  CHECK(attr.asset_report.file_vertices == 4);
  CHECK(attr.asset_report.welded_vertices == 0);
}

TEST_CASE("assimp: a mesh used by two nodes appears twice; points are skipped and counted") {
  Gltf g = square();
  g.nodes = R"([{"mesh":0},{"mesh":0,"translation":[0,0,5]}])";
  g.scene_nodes = "[0,1]";
  g.extra_primitive = R"(,{"attributes":{"POSITION":0},"mode":0})";
  locus::MeshAttributes attr;
  const locus::Mesh m = from_memory(g.gltf(), "gltf", {}, &attr);
  REQUIRE(m.num_vertices() == 8);
  CHECK(m.num_faces() == 4);
  for (int i = 0; i < 4; ++i) CHECK(m.z[size_t(i)] == 0.0);
  for (int i = 4; i < 8; ++i) CHECK(m.z[size_t(i)] == 5.0);
  const locus::AssetReport& r = attr.asset_report;
  CHECK(r.mesh_instances == 2);
  CHECK(r.skipped_meshes == 2);  // the points primitive, once per node
  CHECK(r.skipped_points == 8);
  CHECK(r.file_vertices == 8);
}

TEST_CASE("assimp: a cube with split normals welds 24 vertices into 8; weld = false keeps 24") {
  const Gltf g = split_cube();
  locus::MeshAttributes attr;
  const locus::Mesh m = from_memory(g.glb(), "glb", {}, &attr);
  REQUIRE(m.num_vertices() == 8);
  CHECK(m.num_faces() == 12);
  CHECK(volume(m) == doctest::Approx(1.0));
  const locus::AssetReport& r = attr.asset_report;
  CHECK(r.file_vertices == 24);
  CHECK(r.welded_vertices == 16);
  CHECK(r.collapsed_faces == 0);
  REQUIRE(r.file_to_vertex.size() == 24);
  std::vector<int> copies(8, 0);
  for (size_t i = 0; i < 24; ++i) {
    const int32_t w = r.file_to_vertex[i];
    REQUIRE(w >= 0);
    REQUIRE(w < 8);
    ++copies[size_t(w)];
    // The welded vertex is where the file vertex was.
    CHECK(m.x[size_t(w)] == g.pos[3 * i]);
    CHECK(m.y[size_t(w)] == g.pos[3 * i + 1]);
    CHECK(m.z[size_t(w)] == g.pos[3 * i + 2]);
  }
  for (int c : copies) CHECK(c == 3);  // each cube corner is on 3 faces
  // Welded vertices are numbered in order of their first file vertex.
  CHECK(r.file_to_vertex[0] == 0);
  for (size_t i = 1, seen = 1; i < 24; ++i)
    if (r.file_to_vertex[i] >= int32_t(seen)) CHECK(r.file_to_vertex[i] == int32_t(seen++));

  locus::ReadOptions keep;
  keep.weld = false;
  const locus::Mesh k = from_memory(g.glb(), "glb", keep, &attr);
  REQUIRE(k.num_vertices() == 24);
  CHECK(k.num_faces() == 12);
  CHECK(volume(k) == doctest::Approx(1.0));
  CHECK(attr.asset_report.welded_vertices == 0);
  for (size_t i = 0; i < 24; ++i) {
    CHECK(attr.asset_report.file_to_vertex[i] == int32_t(i));
    CHECK(k.x[i] == g.pos[3 * i]);
  }
}

TEST_CASE("assimp: ASCII STL, welded and not") {
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};  // outward
  std::string s = "solid tet\n";
  for (const auto& t : f) {
    s += "facet normal 0 0 0\n outer loop\n";
    for (int c : t) s += "  vertex " + std::to_string(p[c][0]) + " " + std::to_string(p[c][1]) + " " + std::to_string(p[c][2]) + "\n";
    s += " endloop\nendfacet\n";
  }
  s += "endsolid tet\n";
  locus::MeshAttributes attr;
  const locus::Mesh m = locus::read_mesh(write_file("tet.stl", s), {}, &attr);
  REQUIRE(m.num_vertices() == 4);
  CHECK(m.num_faces() == 4);
  CHECK(attr.asset_report.file_vertices == 12);
  CHECK(attr.asset_report.welded_vertices == 8);
  CHECK(volume(m) == doctest::Approx(1.0 / 6.0));
  for (int i = 0; i < 4; ++i) {  // first occurrences come in the order 0, 2, 1, 3
    const int src = i == 1 ? 2 : i == 2 ? 1 : i;
    CHECK(m.x[size_t(i)] == p[src][0]);
    CHECK(m.y[size_t(i)] == p[src][1]);
    CHECK(m.z[size_t(i)] == p[src][2]);
  }
  locus::ReadOptions keep;
  keep.weld = false;
  const locus::Mesh k = from_memory(s, "stl", keep);
  CHECK(k.num_vertices() == 12);
  CHECK(k.num_faces() == 4);
}

TEST_CASE("assimp: Collada written by hand, quad triangulated, node translation applied, Z_UP kept") {
  const std::string dae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="quad" name="quad"><mesh>
      <source id="quad-pos">
        <float_array id="quad-pos-array" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
        <technique_common><accessor source="#quad-pos-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="quad-vtx"><input semantic="POSITION" source="#quad-pos"/></vertices>
      <polylist count="1"><input semantic="VERTEX" source="#quad-vtx" offset="0"/><vcount>4</vcount><p>0 1 2 3</p></polylist>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="n" name="n"><translate>5 6 7</translate><instance_geometry url="#quad"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
  const locus::Mesh m = locus::read_mesh(write_file("quad.dae", dae));
  REQUIRE(m.num_vertices() == 4);
  REQUIRE(m.num_faces() == 2);
  const double px[4] = {0, 1, 1, 0}, py[4] = {0, 0, 1, 1};
  // The triangulation may start anywhere: check positions as a set and the total area.
  std::vector<int> hit(4, 0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (m.x[size_t(i)] == px[j] + 5 && m.y[size_t(i)] == py[j] + 6 && m.z[size_t(i)] == 7) ++hit[size_t(j)];
  for (int h : hit) CHECK(h == 1);
  double area = 0;
  for (int32_t f = 0; f < 2; ++f) {
    const auto c = m.face(f);
    const size_t a = size_t(c[0]), b = size_t(c[1]), d = size_t(c[2]);
    area += 0.5 * ((m.x[b] - m.x[a]) * (m.y[d] - m.y[a]) - (m.y[b] - m.y[a]) * (m.x[d] - m.x[a]));
  }
  CHECK(area == doctest::Approx(1.0));
}

TEST_CASE("assimp: a .gltf's external buffer is read from its own folder only") {
  const Gltf g = square();
  const std::string bin = g.buffer();
  write_file("ext/square.bin", bin);
  const std::string ok = write_file("ext/square.gltf", g.json("square.bin", bin.size()));
  check_square_placed(locus::read_mesh(ok), 1, false, {0, 0, 0});
  // From memory there is no folder: the external buffer is refused.
  const std::string text = g.json("square.bin", bin.size());
  CHECK(memory_error(text, "gltf").thrown);
  // A buffer outside the folder is never opened, even when it exists.
  write_file("outside.bin", bin);
  check_bad(catch_error([&] { locus::read_mesh(write_file("ext/up.gltf", g.json("../outside.bin", bin.size()))); }),
            {"up.gltf"});
  const std::string abs = (locus_test::scratch_dir() / "assimp" / "outside.bin").string();
  check_bad(catch_error([&] { locus::read_mesh(write_file("ext/abs.gltf", g.json(abs, bin.size()))); }), {"abs.gltf"});
}

TEST_CASE("assimp: hostile asset files are BadInput naming the file, never a crash") {
  const Gltf g = square();
  const std::string glb = g.glb();
  check_bad(catch_error([&] { locus::read_mesh(write_file("empty.glb", "")); }), {"empty.glb", "empty"});
  for (size_t cut : {size_t(3), size_t(12), size_t(20), glb.size() / 2, glb.size() - 4})
    check_bad(memory_error(glb.substr(0, cut), "glb"), {"t.glb"});
  // An index accessor claiming more indices than its buffer view holds.
  Gltf big = square();
  big.index_count = "1000000";
  check_bad(memory_error(big.gltf(), "gltf"), {"t.gltf"});
  big.index_count = "4294967295";
  check_bad(memory_error(big.glb(), "glb"), {"t.glb"});
  // A buffer claiming a gigabyte: embedded, and as a .glb chunk.
  const std::string b = g.buffer();
  check_bad(memory_error(g.json("data:application/octet-stream;base64," + base64(b), uint64_t(1) << 30), "gltf"),
            {"t.gltf"});
  std::string huge = glb;
  const uint32_t gig = uint32_t(1) << 30;
  const size_t bin_len_at = glb.size() - b.size() - 8;
  std::memcpy(&huge[bin_len_at], &gig, 4);
  check_bad(memory_error(huge, "glb"), {"t.glb"});
  // Binary junk with an asset extension, and the FBX magic followed by junk.
  std::string junk;
  for (int i = 0; i < 4096; ++i) junk += char((i * 131 + 7) % 251);
  for (const char* fmt : {"fbx", "dae", "3ds", "x", "3mf", "stl"}) check_bad(memory_error(junk, fmt), {"t."});
  check_bad(memory_error(std::string("Kaydara FBX Binary  \0\x1a\0", 23) + junk, "fbx"), {"t.fbx"});
  check_bad(memory_error("solid x\nendsolid x\n", "stl"), {"t.stl"});
  check_bad(memory_error("{}", "gltf"), {"t.gltf"});
  // Not a format at all.
  check_bad(catch_error([] { locus::read_mesh("mesh.notaformat"); }), {"unknown mesh file extension"});
}

TEST_CASE("assimp: reading prints nothing on stdout or stderr") {
  const Gltf g = split_cube();
  const std::string out = captured_output([&] {
    from_memory(g.glb(), "glb");
    catch_error([&] { from_memory(g.glb().substr(0, 40), "glb"); });
    catch_error([&] { from_memory(std::string(300, 'x'), "fbx"); });
  });
  CHECK_MESSAGE(out.empty(), "printed: " << out);
}

TEST_CASE("assimp: real exports from Debian's assimp-testmodels, when installed") {
  const fs::path root = "/usr/share/assimp/models";
  const std::pair<const char*, int> models[] = {{"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 0},
                                                {"FBX/spider.fbx", 0}, {"Collada/duck.dae", 0},
                                                {"STL/Spider_binary.stl", 0}, {"3MF/box.3mf", 0}};
  if (!fs::exists(root)) {
    MESSAGE("assimp-testmodels not installed (apt-get install assimp-testmodels): skipped");
    return;
  }
  std::vector<int32_t> spider_vertices;  // the same model exported as FBX and as STL
  for (const auto& model : models) {
    const auto& rel = model.first;  // not a structured binding: doctest's lambdas capture it
    const fs::path p = root / rel;
    if (!fs::exists(p)) {
      MESSAGE(std::string(p.string() + " missing: skipped"));
      continue;
    }
    locus::MeshAttributes attr;
    locus::Mesh m;
    const std::string out = captured_output([&] { m = locus::read_mesh(p.string(), {}, &attr); });
    CHECK_MESSAGE(out.empty(), std::string(std::string(rel) + " printed: " + out));
    CHECK(m.num_vertices() > 0);
    CHECK(m.num_faces() > 0);
    CHECK(attr.asset_report.file_vertices == int64_t(attr.asset_report.file_to_vertex.size()));
    CHECK(attr.asset_report.file_vertices - attr.asset_report.welded_vertices == m.num_vertices());
    if (std::string(rel).find("pider") != std::string::npos) spider_vertices.push_back(m.num_vertices());
    MESSAGE(std::string(rel) << ": " << m.num_vertices() << " vertices (" << attr.asset_report.welded_vertices << " welded of "
                << attr.asset_report.file_vertices << "), " << m.num_faces() << " triangles");
  }
  // Welded, both exports give the artist's vertices: the same count.
  if (spider_vertices.size() == 2) CHECK(spider_vertices[0] == spider_vertices[1]);
}
