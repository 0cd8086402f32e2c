// Numerical faults through the `locus` tool: diffusion
// times 0, negative, NaN, infinite, overflowing and huge for every command
// that takes one; zero-area faces, needle triangles, duplicated (unreferenced)
// vertices and meshes with two components. The contract (README "exit
// status"): 2 for a bad value, checked before the file is read; 3 for an
// unsuitable mesh naming the element; 4 for a numerical failure; 0 with finite
// numbers otherwise — never NaN in the output.
// Runs the built binary (LOCUS_BINARY_DIR/locus); skipped with a MESSAGE when
// it has not been built.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kLocus = LOCUS_BINARY_DIR "/locus";

bool have_locus() {
  if (fs::exists(kLocus)) return true;
  MESSAGE("skipped: " << kLocus << " has not been built");
  return false;
}

struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() /
          ("locus-cli-faults-" + std::to_string(::getpid()) + "-" +
           std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
};

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Run {
  int status = -1;  // -1: killed by a signal or not run
  std::string out, err;
};

Run locus(const Scratch& s, const std::string& args) {
  const fs::path out = s.dir / "out.txt", err = s.dir / "err.txt";
  const std::string cmd = "'" + kLocus + "' " + args + " </dev/null >'" + out.string() + "' 2>'" + err.string() + "'";
  const int raw = std::system(cmd.c_str());
  Run r;
  if (raw != -1 && WIFEXITED(raw)) r.status = WEXITSTATUS(raw);
  r.out = read_all(out);
  r.err = read_all(err);
  return r;
}

// An OFF file of a triangle mesh.
std::string off(const std::vector<std::vector<double>>& v, const std::vector<std::vector<int>>& f) {
  std::ostringstream s;
  s.precision(17);
  s << "OFF\n" << v.size() << " " << f.size() << " 0\n";
  for (const auto& p : v) s << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& t : f) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return s.str();
}

// Octahedron (closed, 6 vertices), optionally with a second copy shifted along x.
std::string octahedron(bool two_copies) {
  std::vector<std::vector<double>> v{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<std::vector<int>> f{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  if (two_copies) {
    for (int i = 0; i < 6; ++i) v.push_back({v[i][0] + 5, v[i][1], v[i][2]});
    for (int k = 0; k < 8; ++k) f.push_back({f[k][0] + 6, f[k][1] + 6, f[k][2] + 6});
  }
  return off(v, f);
}

// A 5x5-vertex planar grid (ids j*5+i) split along the (i,j)-(i+1,j+1) diagonals;
// vertex 1 is moved to (0.125, 0.125 + lift): with lift 0 face (0,1,6) is flat.
std::string grid(double lift) {
  std::vector<std::vector<double>> v;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) v.push_back({i / 4.0, j / 4.0, 0});
  v[1] = {0.125, 0.125 + lift, 0};
  std::vector<std::vector<int>> f;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const int a = j * 5 + i;
      f.push_back({a, a + 1, a + 6});
      f.push_back({a, a + 6, a + 5});
    }
  return off(v, f);
}

bool no_nan_in(const std::string& text) {
  std::string t = text;
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return t.find("nan") == std::string::npos;
}

}  // namespace

TEST_CASE("cli faults: bad diffusion times exit 2 naming the option, before the file is read") {
  if (!have_locus()) return;
  Scratch s;
  // The file does not exist: a bad time must be reported first (exit 2, not 3).
  const std::string missing = (s.dir / "missing.off").string();
  const std::vector<std::string> bad_times{"0", "-1", "nan", "NaN", "inf", "-inf", "1e400", "0h2", "-2h2", "nanh2",
                                           "infh2", "h", "1e-400", "abc"};
  // Not listed: an empty value (--t ''), which the commands read as "no --t given"
  // and replace by the default h2 (reported to the CLI owner).
  const std::vector<std::string> commands{"factor '" + missing + "' --t", "heat '" + missing + "' --source 0 --target 1 --t",
                                          "voronoi '" + missing + "' --sites 0 --t", "cvt '" + missing + "' --t",
                                          "adf '" + missing + "' --vertices 0 --t", "hks '" + missing + "' --vertices 0 --ts"};
  for (const std::string& cmd : commands)
    for (const std::string& t : bad_times) {
      const Run r = locus(s, cmd + " '" + t + "'");
      INFO("locus " << cmd << " '" << t << "': " << r.err);
      CHECK(r.status == 2);
      CHECK(r.err.find("--t") != std::string::npos);
    }
  // A list with one bad entry.
  const Run r = locus(s, "hks '" + missing + "' --vertices 0 --ts 1h2,0,2h2");
  INFO(r.err);
  CHECK(r.status == 2);
  for (const char* f : {"0", "-1", "nan", "inf", "1e400"}) {
    for (const char* cmd : {"geodesic", "logmap"}) {
      const std::string opt = std::string(cmd) == "geodesic" ? " --source 0" : " --center 0";
      const Run g = locus(s, std::string(cmd) + " '" + missing + "'" + opt + " --t-factor " + f);
      INFO(cmd << " --t-factor " << f << ": " << g.err);
      CHECK(g.status == 2);
      // The engine names the field (t_factor), the CLI option's name with '_'.
      CHECK(g.err.find("t_factor") != std::string::npos);
    }
  }
}

TEST_CASE("cli faults: huge diffusion times give a numerical failure or finite numbers, never NaN") {
  if (!have_locus()) return;
  Scratch s;
  const std::string mesh = s.write("octa.off", octahedron(false));
  for (const char* t : {"1e300", "1e300h2", "1e-300", "1e-300h2"}) {
    for (const std::string& cmd : {std::string("factor '") + mesh + "' --json --t",
                                   "heat '" + mesh + "' --source 0 --target 1,5 --json --t",
                                   "adf '" + mesh + "' --vertices 0,3 --json --t",
                                   "voronoi '" + mesh + "' --sites 0,1 --json --t"}) {
      const Run r = locus(s, cmd + " " + t);
      INFO("locus " << cmd << " " << t << " -> " << r.status << ": " << r.err << r.out);
      CHECK((r.status == 0 || r.status == 4));
      if (r.status == 0) CHECK(no_nan_in(r.out));
      if (r.status == 4) CHECK(!r.err.empty());
    }
  }
  for (const char* f : {"1e300", "1e-300"}) {
    const Run r = locus(s, "geodesic '" + mesh + "' --source 0 --json --t-factor " + f);
    INFO("geodesic --t-factor " << f << " -> " << r.status << ": " << r.err << r.out);
    if (std::string(f) == "1e300") {  // beyond the heat method's longest time: refused naming the limit
      CHECK(r.status == 2);
      CHECK(r.err.find("at most 1e+06 h^2") != std::string::npos);
      continue;
    }
    CHECK((r.status == 0 || r.status == 4));
    if (r.status == 0) CHECK(no_nan_in(r.out));
  }
}

TEST_CASE("cli faults: zero-area faces, needles, unreferenced duplicates and two components") {
  if (!have_locus()) return;
  Scratch s;
  const std::string flat = s.write("flat.off", grid(0.0));
  // factor has no mesh-level operator; geodesic and adf refuse on the cotan operator
  // (the default, auto, answers on the robust one: tests/tools/robust_operator_cli.cpp).
  for (const std::string& cmd : {std::string("factor"), std::string("geodesic"), std::string("adf")}) {
    std::string extra = cmd == "geodesic" ? " --source 12 --operator cotan" : cmd == "adf" ? " --vertices 12 --operator cotan" : "";
    const Run r = locus(s, cmd + " '" + flat + "'" + extra);
    INFO(cmd << ": " << r.err);
    CHECK(r.status == 3);
    CHECK(r.err.find("face 0") != std::string::npos);  // face (0, 1, 6) is the first face
  }
  const std::string needle = s.write("needle.off", grid(1e-9));
  {
    const Run r = locus(s, "geodesic '" + needle + "' --source 12 --json");
    INFO(r.err << r.out);
    CHECK((r.status == 0 || r.status == 3 || r.status == 4));
    if (r.status == 0) CHECK(no_nan_in(r.out));
    const Run f = locus(s, "factor '" + needle + "' --json");
    INFO(f.err << f.out);
    CHECK((f.status == 0 || f.status == 3 || f.status == 4));
    if (f.status == 0) CHECK(no_nan_in(f.out));
  }
  // An unreferenced copy of vertex 0 of the octahedron (vertex 6).
  const std::string dup = s.write("dup.off", "OFF\n7 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n1 0 0\n"
                                             "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  for (const std::string& cmd : {std::string("factor '") + dup + "'", "geodesic '" + dup + "' --source 0 --operator cotan",
                                 "voronoi '" + dup + "' --sites 0,1 --operator cotan"}) {
    const Run r = locus(s, cmd);
    INFO(cmd << ": " << r.err);
    CHECK(r.status == 3);
    CHECK(r.err.find("6") != std::string::npos);
  }
  // Two components: heat operators are SPD per component; the other component is unreachable.
  const std::string two = s.write("two.off", octahedron(true));
  {
    const Run r = locus(s, "factor '" + two + "' --json");
    INFO(r.err << r.out);
    CHECK(r.status == 0);
    CHECK(no_nan_in(r.out));
    const Run l = locus(s, "factor '" + two + "' --operator laplacian --json");
    INFO(l.err << l.out);
    CHECK(l.status == 0);
    CHECK(no_nan_in(l.out));
    const Run h = locus(s, "heat '" + two + "' --source 0 --target 1,6 --json");
    INFO(h.err << h.out);
    CHECK(h.status == 0);
    CHECK(no_nan_in(h.out));
    const Run g = locus(s, "geodesic '" + two + "' --source 0 --json -o '" + (s.dir / "d.ply").string() + "'");
    INFO(g.err << g.out);
    // The library gives +infinity in the other component (heat_geodesic.hpp);
    // the command writes -1 there (as outside a patch) and counts them.
    CHECK(g.status == 0);
    CHECK(no_nan_in(g.out));
    CHECK(g.out.find("\"unreachable\": 0") == std::string::npos);
    // A log map around a vertex of one component stays in it (the disk stops there).
    const Run lm = locus(s, "logmap '" + two + "' --center 0 --fraction 1 --json");
    INFO(lm.err << lm.out);
    CHECK((lm.status == 0 || lm.status == 3 || lm.status == 4));
    if (lm.status == 0) CHECK(no_nan_in(lm.out));
  }
}
