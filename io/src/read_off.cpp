// Geomview OFF reader (locus/mesh_io.hpp), ASCII form: an optional header
// keyword `[ST][C][N]OFF`, the counts `nv nf [ne]` (on the keyword's line or on
// the following line(s)), nv vertex lines `x y z ...` and nf face lines
// `k i1 .. ik ...`. With attributes asked for, what the keyword announces
// after the coordinates of a vertex line becomes vertex properties: N normals
// (nx ny nz), C colours (red green blue [alpha]; uchar when written as
// integers, else float), ST texture coordinates (u v); a file whose vertex
// lines do not agree on them keeps none (a note says why). The indices' tail
// on a face line (a face colour) is ignored. `#` starts a comment anywhere.
// Not from the thesis: file plumbing.
//
// Records are read line by line (as every OFF writer we know emits them), so
// errors name the line. 4OFF / nOFF (other dimensions) and binary OFF are
// refused with a message saying so.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "locus/io/mesh_checks.hpp"
#include "locus/io/readers.hpp"
#include "locus/io/text_scanner.hpp"

namespace locus::io {

namespace {

struct VertexExtras {
  bool st = false, colour = false, normal = false;
};

// Recognizes the header keyword; returns false if `tok` is not one (the file
// may start directly with the counts, which Geomview allows).
bool header_keyword(std::string_view tok, const LineReader& lines, VertexExtras& extras) {
  std::string_view s = tok;
  if (s.substr(0, 2) == "ST") s.remove_prefix(2), extras.st = true;
  if (!s.empty() && s[0] == 'C') s.remove_prefix(1), extras.colour = true;
  if (!s.empty() && s[0] == 'N') s.remove_prefix(1), extras.normal = true;
  if (!s.empty() && (s[0] == '4' || s[0] == 'n') && s.size() >= 3 && s.substr(s.size() - 3) == "OFF")
    lines.fail("header " + quote(tok) + ": only 3-D OFF is supported (4OFF / nOFF are not)");
  if (s == "OFF") return true;
  int64_t dummy;
  if (parse_int(tok, dummy)) return false;
  lines.fail("expected an OFF header (OFF, COFF, NOFF, CNOFF, STOFF, ...), found " + quote(tok));
}

// The numbers after x y z on the vertex lines, turned into properties when
// every line has the count the keyword announces (normals 3, colours 3 or 4,
// texture coordinates 2; in Geomview's order N, C, ST).
struct ExtraColumns {
  std::vector<double> values;  // row-major, `width` per vertex
  int width = -1;              // -1: no line yet; -2: lines disagree
  bool integers = true;        // colour values all written as integers
  int64_t bad_vertex = -1;
  void add(Fields& f, int64_t v) {
    int n = 0;
    for (std::string_view tok = f.next(); !tok.empty() && tok[0] != '#'; tok = f.next()) {
      double x = 0;
      int64_t i = 0;
      if (!parse_double(tok, x)) {
        n = -1;
        break;
      }
      integers = integers && parse_int(tok, i);
      values.push_back(x);
      ++n;
    }
    if (width == -1) width = n;
    if (n != width && width != -2) {
      width = -2;
      bad_vertex = v;
    }
  }
};

void keep_extras(const VertexExtras& e, ExtraColumns& cols, int64_t nv, const std::string& name, MeshAttributes& a) {
  if (!(e.normal || e.colour || e.st) || nv == 0) return;
  const int fixed = (e.normal ? 3 : 0) + (e.st ? 2 : 0);
  const int colours = e.colour ? cols.width - fixed : 0;
  if (cols.width < 0 || (e.colour && colours != 3 && colours != 4) || (!e.colour && cols.width != fixed)) {
    a.notes.push_back(name + ": the vertex lines do not hold what the OFF keyword announces" +
                      (cols.bad_vertex >= 0 ? " (vertex " + std::to_string(cols.bad_vertex) + " differs)" : std::string()) +
                      "; normals, colours and texture coordinates not kept");
    return;
  }
  const size_t w = static_cast<size_t>(cols.width);
  size_t at = 0;
  auto column = [&](const char* n, VertexProperty::Type t) {
    VertexProperty p{n, t, std::vector<double>(static_cast<size_t>(nv))};
    for (size_t v = 0; v < static_cast<size_t>(nv); ++v) p.values[v] = cols.values[v * w + at];
    ++at;
    a.vertex.push_back(std::move(p));
  };
  if (e.normal)
    for (const char* n : {"nx", "ny", "nz"}) column(n, VertexProperty::Type::Double);
  const auto ct = cols.integers ? VertexProperty::Type::UInt8 : VertexProperty::Type::Float;
  for (int k = 0; k < colours; ++k) column(k == 0 ? "red" : k == 1 ? "green" : k == 2 ? "blue" : "alpha", ct);
  if (e.st)
    for (const char* n : {"u", "v"}) column(n, VertexProperty::Type::Double);
}

// The header: the optional keyword (its extras) and the vertex and face
// counts, possibly spread over several lines; `lines` is left after it.
std::array<int64_t, 2> read_header(LineReader& lines, const std::string& name, VertexExtras& extras) {
  std::string_view line;
  if (!lines.next_content(line)) fail(ErrorCode::BadInput, name + ": no OFF header (the file holds only comments or blanks)");
  Fields fields(line);
  const std::string_view first = fields.next();
  std::vector<int64_t> counts;
  if (!header_keyword(first, lines, extras)) fields = Fields(line);  // no keyword: this line holds counts
  for (;;) {
    for (std::string_view tok = fields.next(); !tok.empty() && counts.size() < 3; tok = fields.next()) {
      if (tok == "BINARY") lines.fail("binary OFF is not supported");
      int64_t c;
      if (!parse_int(tok, c)) lines.fail("expected the vertex, face and edge counts, found " + quote(tok));
      if (c < 0) lines.fail("negative count " + std::to_string(c) + " in the OFF header");
      counts.push_back(c);
    }
    if (counts.size() >= 2) break;
    if (!lines.next_content(line))
      fail_line(name, lines.line_number(), "the file ends inside the OFF header (truncated: counts missing)");
    fields = Fields(line);
  }
  // Counts spread over lines ("3\n1\n0\n"): a following line holding a single
  // integer is the edge count; a vertex line has at least three fields.
  if (counts.size() == 2) {
    LineReader ahead = lines;
    std::string_view peek;
    if (ahead.next_content(peek)) {
      Fields pf(peek);
      int64_t ne;
      if (parse_int(pf.next(), ne) && pf.done()) lines = ahead;
    }
  }
  return {counts[0], counts[1]};
}

// Refuses counts the rest of the file cannot hold before allocating anything.
void check_counts(LineReader& lines, const std::string& name, int64_t nv, int64_t nf, const ReadOptions& opt) {
  if (nv > kMaxCount || nf > kMaxCount)
    lines.fail("counts " + std::to_string(nv) + " vertices / " + std::to_string(nf) +
               " faces exceed what a mesh can index (" + std::to_string(kMaxCount) + ")");
  // A vertex line is at least "0 0 0\n" (6 bytes); a face line at least two
  // ("k\n": invalid, but it must reach the face check to be reported as what
  // it is); the last line may lack its newline.
  const uint64_t need = sat_add(sat_mul(uint64_t(nv), 6), sat_mul(uint64_t(nf), 2));
  if (need > lines.remaining() + 1)
    lines.fail("header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
               " faces, which need at least " + std::to_string(need) + " bytes, but only " +
               std::to_string(lines.remaining()) + " bytes follow (truncated file or corrupt counts)");
  check_budget(name, uint64_t(nv), uint64_t(nf), 3 * uint64_t(nf), opt);
}

void read_vertices(LineReader& lines, const std::string& name, int64_t nv, bool extra_columns, Mesh& m,
                   ExtraColumns& columns) {
  std::string_view line;
  for (int64_t v = 0; v < nv; ++v) {
    if (!lines.next_content(line))
      fail_line(name, lines.line_number(),
                "the file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices (truncated)");
    Fields f(line);
    double c[3];
    for (int k = 0; k < 3; ++k) {
      const std::string_view tok = f.next();
      if (tok.empty())
        lines.fail("vertex " + std::to_string(v) + " has " + std::to_string(k) + " coordinates (expected 3)");
      const std::string bad = parse_coordinate(tok, v, c[k]);
      if (!bad.empty()) lines.fail(bad);
    }
    const std::string bad = vertex_problem(v, c[0], c[1], c[2]);
    if (!bad.empty()) lines.fail(bad);
    m.add_vertex(c[0], c[1], c[2]);
    if (extra_columns) columns.add(f, v);
  }
}

// Face fi's vertex indices from its line into `face`.
void parse_face(LineReader& lines, std::string_view line, int64_t fi, int64_t nv, std::vector<int32_t>& face) {
  Fields f(line);
  const std::string_view ktok = f.next();
  int64_t k;
  if (!parse_int(ktok, k))
    lines.fail("face " + std::to_string(fi) + ": expected the vertex count, found " + quote(ktok));
  if (k < 3)
    lines.fail("face " + std::to_string(fi) + " has " + std::to_string(k) + " vertices (a face needs at least 3)");
  // A line is at most kMaxLineBytes, so a count beyond half of that cannot be
  // honest; checking first keeps the reserve below bounded.
  if (k > int64_t(kMaxLineBytes / 2))
    lines.fail("face " + std::to_string(fi) + " declares " + std::to_string(k) + " vertices, more than the line can hold");
  face.clear();
  for (int64_t j = 0; j < k; ++j) {
    const std::string_view tok = f.next();
    if (tok.empty())
      lines.fail("face " + std::to_string(fi) + " declares " + std::to_string(k) + " vertices but lists only " +
                 std::to_string(j) + " (truncated face)");
    int64_t idx;
    if (!parse_int(tok, idx))
      lines.fail("face " + std::to_string(fi) + ": expected a vertex index, found " + quote(tok));
    if (idx < 0 || idx >= nv)
      lines.fail("face " + std::to_string(fi) + " references vertex " + std::to_string(idx) + " but the file has " +
                 std::to_string(nv) + " vertices (index out of range)");
    face.push_back(static_cast<int32_t>(idx));
  }
  // The rest of the line (a face colour) is ignored.
}

void read_faces(LineReader& lines, const std::string& name, int64_t nv, int64_t nf, Mesh& m) {
  std::string_view line;
  std::vector<int32_t> face;
  for (int64_t fi = 0; fi < nf; ++fi) {
    if (!lines.next_content(line))
      fail_line(name, lines.line_number(),
                "the file ends after " + std::to_string(fi) + " of " + std::to_string(nf) + " faces (truncated)");
    parse_face(lines, line, fi, nv, face);
    const std::string bad = face_problem(fi, face);
    if (!bad.empty()) lines.fail(bad);
    if (static_cast<int64_t>(m.face_vertices.size() + face.size()) > kMaxCount)
      lines.fail("more face corners than a mesh can index (" + std::to_string(kMaxCount) + ")");
    m.face_vertices.insert(m.face_vertices.end(), face.begin(), face.end());
    m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
  }
}

}  // namespace

Mesh read_off(std::string_view data, const std::string& name, const ReadOptions& opt, MeshAttributes* attributes) {
  LineReader lines(data, name);
  VertexExtras extras;
  const auto [nv, nf] = read_header(lines, name, extras);
  check_counts(lines, name, nv, nf, opt);

  Mesh m;
  m.x.reserve(nv); m.y.reserve(nv); m.z.reserve(nv);
  // Reserve only what the bytes can hold as valid triangles ("3 0 1 2\n" is
  // 8 bytes), so hostile face counts cannot inflate the allocation.
  const int64_t nf_fit = std::min<int64_t>(nf, static_cast<int64_t>(lines.remaining() / 8) + 1);
  m.face_offsets.reserve(nf_fit + 1);
  m.face_vertices.reserve(3 * nf_fit);
  ExtraColumns columns;
  read_vertices(lines, name, nv, attributes && (extras.normal || extras.colour || extras.st), m, columns);
  read_faces(lines, name, nv, nf, m);
  // Whatever follows the faces (edges, trailing comments) is not mesh data.
  finish_mesh(m, name);
  if (attributes) keep_extras(extras, columns, nv, name, *attributes);
  return m;
}

}  // namespace locus::io
