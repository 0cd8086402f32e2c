// libFuzzer target for the option parser of the `locus` tool: the
// CommandTable of tools/cli with every command registered (as main.cpp does),
// fed a fuzzed argv. The input is the argument list, one argument per line
// ("geodesic\nt.off\n--source\n3"); argv[0] is "locus".
//
// Outcomes: CommandTable::run must return one of the contract's statuses
// 0, 2, 3, 4, 5 (README "exit status"); 70 (an internal error, i.e. an
// exception that is not a locus::Error) or anything else aborts as a finding,
// as do crashes, sanitizer reports and hangs.
//
// Keeping the bodies cheap: each input runs in a scratch directory holding
// three tiny meshes (t.off: a 19-vertex disk, s.ply: an icosahedron, q.obj: a
// 3x3 quad grid), rewritten before every input, and every other file there is
// deleted after it. Inputs are rejected (return -1, not kept) when an argument
// contains '/' (no file outside the scratch directory is read or written),
// when a number in an argument exceeds 40 (vertex ids, counts, iterations,
// repeats, threads), except in the values of options that are not sizes
// (--t, --ts, --t-factor, --eps, --offset, ...), or when --subdivide asks
// for more than 2. A fresh table is built for every input, so no option value
// leaks from one input into the next.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <streambuf>
#include <string>
#include <vector>

#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/mesh_io.hpp"
#include "tools/cli/cli_common.hpp"

namespace {

struct NullBuffer : std::streambuf {
  int overflow(int c) override { return c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

const char* const kFixtures[] = {"t.off", "s.ply", "q.obj"};

void write_fixtures() {
  static const locus::Mesh disk = locus::make_disk(2);
  static const locus::Mesh ico = locus::make_icosphere(0);
  static const locus::Mesh quads = [] {
    locus::Mesh m;
    for (int j = 0; j <= 3; ++j)
      for (int i = 0; i <= 3; ++i) m.add_vertex(i, j, 0.1 * ((i * 7 + j * 3) % 5));
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const int32_t a = j * 4 + i;
        const int32_t q[4] = {a, a + 1, a + 5, a + 4};
        m.add_face(q);
      }
    return m;
  }();
  locus::write_mesh(kFixtures[0], disk);
  locus::write_mesh(kFixtures[1], ico);
  locus::write_mesh(kFixtures[2], quads);
}

void remove_other_files() {
  DIR* d = opendir(".");
  if (!d) return;
  std::vector<std::string> doomed;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    bool fixture = false;
    for (const char* f : kFixtures) fixture = fixture || name == f;
    if (!fixture) doomed.push_back(name);
  }
  closedir(d);
  for (const std::string& name : doomed) {
    if (std::remove(name.c_str()) != 0) rmdir(name.c_str());
  }
}

// Option names whose values are not sizes: any magnitude is allowed there.
bool unbounded_option(const std::string& name) {
  static const char* const names[] = {"--t",      "--ts",           "--t-factor",    "--eps",
                                      "--offset", "--load-density", "--anisotropy",  "--regularization",
                                      "--fraction", "--roi-fraction", "--seed"};
  for (const char* n : names)
    if (name == n) return true;
  return false;
}

// Largest absolute value of the numbers written in `s` (digits, '.', exponent).
double largest_number(const std::string& s) {
  double big = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const bool starts = (s[i] >= '0' && s[i] <= '9') || (s[i] == '.' && i + 1 < s.size() && s[i + 1] >= '0' && s[i + 1] <= '9');
    if (!starts || (i > 0 && ((s[i - 1] >= '0' && s[i - 1] <= '9') || s[i - 1] == '.'))) continue;
    char* end = nullptr;
    const double v = std::strtod(s.c_str() + i, &end);
    if (std::isnan(v) || std::fabs(v) > big) big = std::isnan(v) ? 1e308 : std::fabs(v);
  }
  return big;
}

std::string option_name(const std::string& arg) {
  if (arg.size() < 2 || arg[0] != '-') return "";
  const size_t eq = arg.find('=');
  return eq == std::string::npos ? arg : arg.substr(0, eq);
}

// True when the argument list may run: see the file comment. A number counts
// against the option it belongs to: the option of its own argument (--name or
// --name=value) or, for a bare value, the option just before it.
bool acceptable(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.find('/') != std::string::npos) return false;
    const std::string own = option_name(a);
    const std::string context = !own.empty() ? own : (i > 0 ? option_name(args[i - 1]) : "");
    const double big = largest_number(a);
    if (context == "--subdivide" && big > 2) return false;
    if (!unbounded_option(context) && big > 40) return false;
  }
  return true;
}

// The scratch directory, and the directory libFuzzer was started in (its
// corpus and artifact paths are relative to it): each input runs inside the
// scratch directory and returns to the start directory afterwards.
std::string g_scratch, g_home;

void enter(const std::string& dir) {
  if (chdir(dir.c_str()) != 0) {
    std::perror(("fuzz_cli_options: chdir " + dir).c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* tmp = std::getenv("TMPDIR");
  std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/locus_fuzz_cli_XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) {
    std::perror("fuzz_cli_options: scratch directory");
    std::abort();
  }
  g_scratch = buf.data();
  char cwd[4096];
  if (!getcwd(cwd, sizeof cwd)) {
    std::perror("fuzz_cli_options: getcwd");
    std::abort();
  }
  g_home = cwd;
  static NullBuffer null;
  std::cout.rdbuf(&null);
  std::cerr.rdbuf(&null);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args{"locus"};
  std::string cur;
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(static_cast<char>(data[i]));
    }
  }
  if (!cur.empty()) args.push_back(cur);
  if (args.size() > 40) return -1;
  if (!acceptable(std::vector<std::string>(args.begin() + 1, args.end()))) return -1;

  enter(g_scratch);
  write_fixtures();
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int status = -1;
  {
    locus::cli::CommandTable table("locus", "locus (fuzzed)");
    locus::cli::register_info_command(table);
    locus::cli::register_perfect_laplacian_commands(table);
    locus::cli::register_factor_command(table);
    locus::cli::register_deform_command(table);
    locus::cli::register_local_solve_commands(table);
    locus::cli::register_voronoi_command(table);
    locus::cli::register_cvt_command(table);
    locus::cli::register_geodesic_commands(table);
    status = table.run(static_cast<int>(args.size()), argv.data());
  }
  remove_other_files();
  enter(g_home);
  if (status != 0 && status != 2 && status != 3 && status != 4 && status != 5) {
    std::fprintf(stderr, "fuzz_cli_options: exit status %d for:", status);
    for (const std::string& a : args) std::fprintf(stderr, " [%s]", a.c_str());
    std::fprintf(stderr, "\n");
    std::abort();
  }
  return 0;
}
