// Tests of the `locus` command-line tool as users run it: the built binary
// (LOCUS_BINARY_DIR/locus) on files written here. Hostile files must give exit
// status 3 and a message naming the problem, bad usage exit 2, cancellation
// exit 5; `info --json` and `factor --json` must report numbers that are known
// by hand for small meshes (octahedron, cube, square, two components).
// Skipped with a MESSAGE when the CLI has not been built.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <thread>

namespace fs = std::filesystem;

namespace {

const std::string kBinary = LOCUS_BINARY_DIR "/locus";

bool have_binary() {
  if (fs::exists(kBinary)) return true;
  MESSAGE("skipped: " << kBinary << " has not been built");
  return false;
}

// A scratch directory removed at the end of the test case.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("locus-cli-test-" + std::to_string(::getpid()) + "-" +
                                        std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name, const std::string& content) const {
    const fs::path p = path / name;
    std::ofstream(p, std::ios::binary) << content;
    return p.string();
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Result {
  int status = -1;  // exit status, or -1 if the process did not exit normally (crash, signal)
  std::string out, err;
};

// Runs `locus <args>` through the shell with stdin from /dev/null (as in CI).
Result run_locus(const TempDir& dir, const std::string& args) {
  const fs::path out = dir.path / "stdout.txt", err = dir.path / "stderr.txt";
  const std::string cmd = "'" + kBinary + "' " + args + " <" + "/dev/null >'" + out.string() + "' 2>'" + err.string() + "'";
  const int raw = std::system(cmd.c_str());
  Result r;
  if (raw != -1 && WIFEXITED(raw)) r.status = WEXITSTATUS(raw);
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool mentions_any(const std::string& text, std::initializer_list<const char*> words) {
  const std::string t = lower(text);
  for (const char* w : words)
    if (t.find(lower(w)) != std::string::npos) return true;
  return false;
}

// Regular octahedron: vertices at +-e_i, 8 outward-oriented triangles.
const char* kOctahedronVertices =
    "1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n";
const char* kOctahedronFaces =
    "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";

std::string octahedron_off() { return std::string("OFF\n6 8 0\n") + kOctahedronVertices + kOctahedronFaces; }

}  // namespace

TEST_CASE("cli: info --json on an octahedron reports the numbers known by hand") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
  REQUIRE_MESSAGE(r.status == 0, r.err);
  const nlohmann::json j = nlohmann::json::parse(r.out);  // stdout is exactly one JSON object
  CHECK(j["n_vertices"] == 6);
  CHECK(j["n_faces"] == 8);
  CHECK(j["n_edges"] == 12);
  CHECK(j["face_degree_histogram"] == nlohmann::json{{"3", 8}});
  CHECK(j["components"] == 1);
  CHECK(j["boundary_loops"] == 0);
  CHECK(j["euler_characteristic"] == 2);  // V - E + F = 6 - 12 + 8
  CHECK(j["genus"] == 0);
  CHECK(j["manifold"] == true);
  CHECK(j["non_manifold_edges"] == 0);
  CHECK(j["non_manifold_vertices"] == 0);
  CHECK(j["degenerate_faces"] == 0);
  CHECK(j["unreferenced_vertices"] == 0);
  CHECK(j["bbox"]["min"] == nlohmann::json{-1.0, -1.0, -1.0});
  CHECK(j["bbox"]["max"] == nlohmann::json{1.0, 1.0, 1.0});
  CHECK(j["mean_edge_length"].get<double>() == doctest::Approx(std::sqrt(2.0)).epsilon(1e-12));
  CHECK(j["timings"]["load_s"].get<double>() >= 0);
  CHECK(j["timings"]["analysis_s"].get<double>() >= 0);
  CHECK(j["input"]["file"] == mesh);
}

TEST_CASE("cli: info --json on other small meshes: open square, quad cube, two components, subdivision") {
  if (!have_binary()) return;
  TempDir dir;
  SUBCASE("open square of two triangles: one boundary loop, chi = 1") {
    const std::string mesh = dir.file("square.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["n_edges"] == 5);
    CHECK(j["boundary_loops"] == 1);
    CHECK(j["euler_characteristic"] == 1);
    CHECK(j["genus"] == 0);  // (2 - chi - b) / 2 = (2 - 1 - 1) / 2
    CHECK(j["mean_edge_length"].get<double>() == doctest::Approx((4 + std::sqrt(2.0)) / 5).epsilon(1e-12));
  }
  SUBCASE("cube of six quads: degree histogram {4: 6}") {
    const std::string mesh = dir.file(
        "cube.off",
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["face_degree_histogram"] == nlohmann::json{{"4", 6}});
    CHECK(j["n_edges"] == 12);
    CHECK(j["euler_characteristic"] == 2);
    CHECK(j["mean_edge_length"].get<double>() == doctest::Approx(1.0).epsilon(1e-12));
  }
  SUBCASE("two disjoint octahedra: two components, genus undefined (null)") {
    std::string off = "OFF\n12 16 0\n";
    off += kOctahedronVertices;
    off += "4 0 0\n2 0 0\n3 1 0\n3 -1 0\n3 0 1\n3 0 -1\n";
    off += kOctahedronFaces;
    std::istringstream faces(kOctahedronFaces);
    int k, a, b, c;
    while (faces >> k >> a >> b >> c)
      off += "3 " + std::to_string(a + 6) + " " + std::to_string(b + 6) + " " + std::to_string(c + 6) + "\n";
    const std::string mesh = dir.file("two.off", off);
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["components"] == 2);
    CHECK(j["euler_characteristic"] == 4);
    CHECK(j["genus"].is_null());
    CHECK(j["bbox"]["max"] == nlohmann::json{4.0, 1.0, 1.0});
  }
  SUBCASE("--subdivide 1: V + E vertices, 4F faces, 2E + 3F edges, same Euler characteristic") {
    const std::string mesh = dir.file("octahedron.off", octahedron_off());
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --subdivide 1 --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["n_vertices"] == 18);
    CHECK(j["n_faces"] == 32);
    CHECK(j["n_edges"] == 48);
    CHECK(j["euler_characteristic"] == 2);
    CHECK(j["mean_edge_length"].get<double>() == doctest::Approx(std::sqrt(2.0) / 2).epsilon(1e-12));
    CHECK(j["input"]["subdivide"] == 1);
  }
}

TEST_CASE("cli: info reports problems of a readable mesh and still exits 0") {
  if (!have_binary()) return;
  TempDir dir;
  SUBCASE("non-manifold edge (three triangles on edge 0-1)") {
    const std::string mesh = dir.file(
        "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["manifold"] == false);
    CHECK(j["non_manifold_edges"] == 1);
    CHECK(j["genus"].is_null());
  }
  SUBCASE("unreferenced vertex") {
    const std::string mesh =
        dir.file("unref.off", std::string("OFF\n7 8 0\n") + kOctahedronVertices + "5 5 5\n" + kOctahedronFaces);
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["unreferenced_vertices"] == 1);
    CHECK(j["n_vertices"] == 7);
  }
  SUBCASE("zero-area triangle") {
    const std::string mesh = dir.file("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    const Result r = run_locus(dir, "info " + quoted(mesh) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    CHECK(nlohmann::json::parse(r.out)["degenerate_faces"] == 1);
  }
  SUBCASE("human-readable output without --json") {
    const std::string mesh = dir.file("octahedron.off", octahedron_off());
    const Result r = run_locus(dir, "info " + quoted(mesh));
    REQUIRE_MESSAGE(r.status == 0, r.err);
    CHECK(r.out.find("vertices 6, faces 8, edges 12") != std::string::npos);
    CHECK(r.out.find("manifold yes") != std::string::npos);
  }
}

TEST_CASE("cli: factor --json on an octahedron: sizes, default t = h^2, residuals") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  const Result r = run_locus(dir, "factor " + quoted(mesh) + " --json --repeat 3");
  REQUIRE_MESSAGE(r.status == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["n"] == 6);
  CHECK(j["nnz_A"] == 18);  // lower triangle: 6 diagonal + 12 edges
  // Eliminating any vertex of the octahedron joins its 4 neighbors into a
  // clique, leaving K5: nnz(L) = 6 + 4 + 10 = 20 for every ordering.
  CHECK(j["nnz_L_exact"] == 20);
  CHECK(j["nnz_L"].get<int64_t>() >= 20);
  CHECK(j["nnz_L"].get<int64_t>() <= 21);  // a dense 6x6 lower triangle at most
  CHECK(j["supernodes"].get<int>() >= 1);
  CHECK(j["etree_height"].get<int>() >= 5);  // K5 after the first elimination: a chain of 5 above it
  CHECK(j["t"].get<double>() == doctest::Approx(2.0).epsilon(1e-12));  // h = sqrt(2)
  CHECK(j["residual"].get<double>() < 1e-12);
  CHECK(j["residual8"].get<double>() < 1e-12);
  CHECK(j["solve8_lane0_vs_solve"].get<double>() < 1e-12);
  CHECK(j["repeats"] == 3);
  for (const char* k : {"order_s", "symbolic_s", "numeric_s", "solve_s", "solve8_s"}) CHECK(j[k].get<double>() >= 0);
}

TEST_CASE("cli: factor --t accepts multiples of h^2 and absolute times; --operator laplacian; --subdivide") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  const Result a = run_locus(dir, "factor " + quoted(mesh) + " --json --t 3h2");
  REQUIRE_MESSAGE(a.status == 0, a.err);
  CHECK(nlohmann::json::parse(a.out)["t"].get<double>() == doctest::Approx(6.0).epsilon(1e-12));  // 3 h^2, h^2 = 2
  const Result b = run_locus(dir, "factor " + quoted(mesh) + " --json --t 0.25");
  REQUIRE_MESSAGE(b.status == 0, b.err);
  CHECK(nlohmann::json::parse(b.out)["t"].get<double>() == 0.25);
  const Result c = run_locus(dir, "factor " + quoted(mesh) + " --json --operator laplacian --subdivide 2 --threads 1");
  REQUIRE_MESSAGE(c.status == 0, c.err);
  const auto jc = nlohmann::json::parse(c.out);
  CHECK(jc["n"] == 66);  // 6 + 12 + 48 vertices after two 1:4 subdivisions
  CHECK(jc["operator"] == "laplacian");
  // -L + eps M with eps = 1e-8 relative is ill-conditioned (~1e8): the residual is still tiny.
  CHECK(jc["residual"].get<double>() < 1e-6);
}

TEST_CASE("cli: a numerically singular operator is a numerical failure (exit 4), never a quiet answer") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  // t = 1e200: M vanishes next to t L, whose constant null vector makes the matrix singular in floating point.
  // t = 1e308: the entries overflow to infinity.
  for (const char* t : {"1e200", "1e308"}) {
    CAPTURE(t);
    const Result r = run_locus(dir, "factor " + quoted(mesh) + " --json --t " + t);
    CAPTURE(r.err);
    CHECK(r.status == 4);
    CHECK(r.out.empty());
    // The error line (after at most the loader's note on the operator it chose).
    CHECK((r.err.rfind("locus: error: ", 0) == 0 || r.err.find("\nlocus: error: ") != std::string::npos));
    CHECK(mentions_any(r.err, {"residual", "positive definite", "not finite"}));
  }
}

TEST_CASE("cli: factor gives the same ordering and result for any thread count (DESIGN.md: deterministic)") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  // --subdivide 6: 16386 vertices, large enough for the ordering to dissect in parallel.
  const std::string args = "factor " + quoted(mesh) + " --subdivide 6 --json --threads ";
  const Result one = run_locus(dir, args + "1");
  REQUIRE_MESSAGE(one.status == 0, one.err);
  const auto j1 = nlohmann::json::parse(one.out);
  REQUIRE(j1["n"] == 16386);
  for (int run = 0; run < 3; ++run) {
    CAPTURE(run);
    const Result two = run_locus(dir, args + "2");
    REQUIRE_MESSAGE(two.status == 0, two.err);
    const auto j2 = nlohmann::json::parse(two.out);
    CHECK(j2["nnz_L_exact"] == j1["nnz_L_exact"]);
    CHECK(j2["etree_height"] == j1["etree_height"]);
    CHECK(j2["supernodes"] == j1["supernodes"]);
    CHECK(j2["residual"] == j1["residual"]);  // bit-identical factor and solve
  }
}

TEST_CASE("cli: -o writes the loaded mesh, which reads back with the same counts") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  for (const char* ext : {".off", ".obj", ".ply"}) {
    CAPTURE(ext);
    const std::string out = (dir.path / (std::string("sub") + ext)).string();
    const Result w = run_locus(dir, "info " + quoted(mesh) + " --subdivide 1 -o " + quoted(out));
    REQUIRE_MESSAGE(w.status == 0, w.err);
    const Result r = run_locus(dir, "info " + quoted(out) + " --json");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j["n_vertices"] == 18);
    CHECK(j["n_faces"] == 32);
    CHECK(j["genus"] == 0);
  }
}

TEST_CASE("cli: hostile files make factor exit 3 with a message naming the problem") {
  if (!have_binary()) return;
  TempDir dir;
  struct Case {
    const char* name;
    std::string content;
    std::initializer_list<const char*> words;  // the message must contain one of these
  };
  std::string garbage(4096, '\0');
  uint64_t s = 0x2545f4914f6cdd1dULL;
  for (char& c : garbage) {
    s ^= s << 13; s ^= s >> 7; s ^= s << 17;  // xorshift64: fixed bytes, NULs and high bytes included
    c = static_cast<char>(s >> 56);
  }
  const Case cases[] = {
      {"empty.off", "", {"empty", "header", "end of file", "eof", "truncated"}},
      {"truncated.off", "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1\n", {"truncated", "end of file", "eof", "expected", "missing"}},
      {"nan.off", std::string("OFF\n6 8 0\n1 0 0\nnan 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n") + kOctahedronFaces,
       {"nan", "finite", "coordinate"}},
      {"out_of_range.off", std::string("OFF\n6 8 0\n") + kOctahedronVertices + "3 0 2 17\n" +
                               std::string(kOctahedronFaces).substr(8),
       {"17", "range"}},
      {"two_vertices.off", std::string("OFF\n6 2 0\n") + kOctahedronVertices + "2 0 1\n3 0 2 4\n",
       {"2 vertices", "fewer than 3", "at least 3", "less than 3", "< 3"}},
      {"repeated.off", std::string("OFF\n6 2 0\n") + kOctahedronVertices + "3 0 0 1\n3 0 2 4\n",
       {"repeat", "twice", "distinct", "duplicate", "more than once"}},
      {"non_manifold.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
       {"manifold"}},
      {"zero_area.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 2\n3 0 3 1\n", {"degenerate", "zero area", "area"}},
      {"unreferenced.off", std::string("OFF\n7 8 0\n") + kOctahedronVertices + "5 5 5\n" + kOctahedronFaces,
       {"unreferenced", "not referenced", "unused"}},
      // Quads are triangulated on load; a self-crossing one cannot be.
      {"bowtie.off", "OFF\n4 1 0\n0 0 0\n1 1 0\n1 0 0\n0 1 0\n4 0 1 2 3\n", {"face 0", "cross"}},
      {"garbage.off", garbage, {"off", "header", "expected", "invalid", "magic"}},
      {"garbage.ply", "ply\nformat binary_little_endian 1.0\n" + garbage, {"ply", "header", "expected", "invalid"}},
      {"huge.off", "OFF\n2000000000 2000000000 0\n0 0 0\n",
       {"2000000000", "too large", "exceed", "limit", "bytes", "memory"}},
      {"huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n",
       {"4000000000", "too large", "exceed", "limit", "bytes", "memory", "range"}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const std::string path = dir.file(c.name, c.content);
    const Result r = run_locus(dir, "factor " + quoted(path) + " --json");
    CAPTURE(r.err);
    CHECK(r.status == 3);
    CHECK(r.out.empty());  // no half JSON object on stdout
    // The error line (after at most the loader's note on the operator it chose).
    CHECK((r.err.rfind("locus: error: ", 0) == 0 || r.err.find("\nlocus: error: ") != std::string::npos));
    CHECK(r.err.find(c.name) != std::string::npos);  // names the file
    // The problem must be named in the message itself, not only in the file name.
    std::string message = r.err;
    for (size_t at; (at = message.find(c.name)) != std::string::npos;) message.erase(at, std::string(c.name).size());
    CHECK(mentions_any(message, c.words));
  }
}

TEST_CASE("cli: a directory, a missing file, subdividing polygons: exit 3") {
  if (!have_binary()) return;
  TempDir dir;
  {
    const fs::path sub = dir.path / "folder.off";  // a directory with a mesh extension
    fs::create_directories(sub);
    const Result r = run_locus(dir, "factor " + quoted(sub.string()));
    CHECK(r.status == 3);
    // The error line (after at most the loader's note on the operator it chose).
    CHECK((r.err.rfind("locus: error: ", 0) == 0 || r.err.find("\nlocus: error: ") != std::string::npos));
    CHECK(mentions_any(r.err, {"directory", "not a regular file"}));
  }
  {
    const Result r = run_locus(dir, "info " + quoted((dir.path / "missing.off").string()));
    CHECK(r.status == 3);
    CHECK(r.err.find("missing.off") != std::string::npos);
  }
  {
    const std::string quads = dir.file(
        "cube.off",
        "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
        "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
    const Result r = run_locus(dir, "info " + quoted(quads) + " --subdivide 1");
    CHECK(r.status == 3);
    CHECK(r.err.find("face 0") != std::string::npos);
  }
}

TEST_CASE("cli: bad usage exits 2 before touching the file") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  const std::string missing = quoted((dir.path / "missing.off").string());
  const std::string bad[] = {
      "",
      "frobnicate " + quoted(mesh),
      "info",
      "info " + quoted(mesh) + " --bogus",
      "info " + quoted(mesh) + " extra-positional",
      "info " + quoted(mesh) + " --threads -1",
      "info " + quoted(mesh) + " --threads many",
      "info " + quoted(mesh) + " --subdivide -1",
      "factor " + quoted(mesh) + " --t abc",
      "factor " + quoted(mesh) + " --t -1",
      "factor " + quoted(mesh) + " --t 0h2",
      "factor " + quoted(mesh) + " --t nan",
      "factor " + quoted(mesh) + " --operator foo",
      "factor " + quoted(mesh) + " --operator laplacian --t 2h2",
      "factor " + quoted(mesh) + " --repeat 0",
      "factor " + missing + " --t abc",  // usage is checked before the file is read
      // Outputs are checked before the file is read too: extension,
      // folder, target kind, and formats that cannot hold the result.
      "info " + missing + " -o " + quoted((dir.path / "x.stl").string()),
      "info " + missing + " -o " + quoted((dir.path / "no" / "such" / "x.obj").string()),
      "info " + missing + " -o " + quoted(dir.path.string()),
      "geodesic " + missing + " --source 0 --preview " + quoted((dir.path / "no" / "p.png").string()),
      "geodesic " + missing + " --source 0 --preview " + quoted((dir.path / "p.jpg").string()),
      "factor " + missing + " --save " + quoted((dir.path / "no" / "f.locus").string()),
      "logmap " + missing + " --center 0 -o " + quoted((dir.path / "l.off").string()),
      "param " + missing + " -o " + quoted((dir.path / "p.off").string()),
      "heat " + missing + " --source 0 --target 1 -o " + quoted((dir.path / "h.ply").string()),
      "nncoords " + missing + " --sites 0,1,2 --point 0,1,0,0 -o " + quoted((dir.path / "n.ply").string()),
      "voronoi " + missing + " --random 3 -o " + quoted((dir.path / "v.off").string()),
  };
  for (const std::string& args : bad) {
    CAPTURE(args);
    const Result r = run_locus(dir, args);
    CHECK(r.status == 2);
    CHECK(r.out.empty());
    // The error line (after at most the loader's note on the operator it chose).
    CHECK((r.err.rfind("locus: error: ", 0) == 0 || r.err.find("\nlocus: error: ") != std::string::npos));
  }
  const Result help = run_locus(dir, "--help");
  CHECK(help.status == 0);
  CHECK(help.out.find("factor") != std::string::npos);
  CHECK(help.out.find("info") != std::string::npos);
}

// Whether process `pid` runs `program` (its argv[0] after exec) and has a handler
// installed for `sig` (SigCgt in /proc/PID/status). Before the exec the forked
// child still carries the test runner's handlers (doctest catches SIGINT).
static bool catches_signal(pid_t pid, const std::string& program, int sig) {
  std::ifstream cmdline("/proc/" + std::to_string(pid) + "/cmdline");
  std::string argv0;
  if (!std::getline(cmdline, argv0, '\0') || argv0 != program) return false;
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1u;
  return false;
}

TEST_CASE("cli: SIGINT cancels a long run with exit status 5") {
  if (!have_binary()) return;
  TempDir dir;
  const std::string mesh = dir.file("octahedron.off", octahedron_off());
  const std::string err = (dir.path / "cancel-stderr.txt").string();
  // --subdivide 9 makes ~1M vertices: seconds of work, so the signal arrives mid-run.
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    std::FILE* e = std::freopen(err.c_str(), "w", stderr);
    std::FILE* o = std::freopen("/dev/null", "w", stdout);
    if (!e || !o) ::_exit(127);
    ::execl(kBinary.c_str(), "locus", "factor", mesh.c_str(), "--subdivide", "9", "--json", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Signal only once the CLI catches SIGINT: a slow start (a sanitized build on a
  // loaded machine) would otherwise meet the default action and die of the signal.
  for (int i = 0; i < 600 && !catches_signal(pid, "locus", SIGINT); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGINT);
  int raw = 0;
  pid_t done = 0;
  // A cancelled run stops at the next phase boundary; give it 60 s, then kill it.
  for (int i = 0; i < 600 && (done = ::waitpid(pid, &raw, WNOHANG)) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (done == 0) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &raw, 0);
    FAIL("locus did not stop within 60 s of SIGINT");
  }
  REQUIRE(WIFEXITED(raw));
  CHECK(WEXITSTATUS(raw) == 5);
  CHECK(slurp(err).find("cancelled") != std::string::npos);
}
