// Wavefront OBJ reader (locus/mesh_io.hpp): `v x y z [w]` vertices and `f`
// polygon faces with corners written `v`, `v/vt`, `v//vn` or `v/vt/vn`,
// positive (1-based) or negative (relative to the vertices read so far)
// indices. With attributes asked for, `vt` and `vn` become per-vertex u v and
// nx ny nz when every corner of a vertex names the same values (else a note:
// a seam cannot be kept per vertex), and a locus '#vp' block (written by
// write_mesh: "#locus vertex-properties NAME:TYPE ..." then one "#vp" line per
// vertex) becomes named properties. Every other statement (g, o, s, usemtl,
// mtllib, l, p, ...), comments and blank lines are ignored. Not from the
// thesis: file plumbing.
//
// Why a hand-written parser and not Debian's libtinyobjloader-dev
// (tinyobjloader 2.0.0~rc10, double build): measured on a 5,004,169-vertex /
// 9,999,392-triangle OBJ (451 MB, a jittered grid), -O3, same machine, median
// of 3 repetitions in one process (the 2-core machine was shared, so the ratio
// is the figure that counts):
//   tinyobj::LoadObj (triangulate=false) + copy to Mesh   9.86 s, peak RSS 1.93 GB
//   this reader (read_mesh)                                1.64 s, peak RSS 0.87 GB
// That is 6x slower, and tinyobjloader is also unsafe for our contract on
// hostile input (checked with that build): "v nan 0 0" and "v abc 0 0" load as
// 0 without a word, "1e999" loads as inf, "f 1 2 -9" on 3 vertices returns
// index -6 with no error or warning, an index past the last vertex returns
// success with only a warning string, and repeated corners pass. Wrapping it
// would mean re-validating everything without line numbers. So: a direct
// parser over the whole buffer, std::from_chars for numbers, and every
// refusal naming the file, the line and the face or vertex (DESIGN.md "Input
// is hostile").
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "locus/io/mesh_checks.hpp"
#include "locus/io/readers.hpp"
#include "locus/io/text_scanner.hpp"

namespace locus::io {

namespace {

// Characters allowed after the vertex index of a face corner ("/vt/vn" parts,
// which we do not keep but still require to look like indices).
bool corner_tail_ok(std::string_view tail) {
  for (char c : tail)
    if (!((c >= '0' && c <= '9') || c == '/' || c == '-' || c == '+')) return false;
  return true;
}

// A positive index that named a vertex not read yet; legal only if the vertex
// appears later in the file, so it is checked once the whole file is read.
struct ForwardRef {
  int64_t line;
  int64_t face;
  int64_t index;  // 1-based, as written
};

// The vt / vn a vertex's corners name: one value set per vertex, or a conflict.
struct CornerAttribute {
  std::vector<std::array<double, 3>> table;  // vt (u, v, 0) or vn (x, y, z), in file order
  std::vector<int64_t> of_vertex;            // per vertex: index into table, -1 none, -2 conflicting
  int64_t conflict_vertex = -1;
  void name(int64_t vertex, int64_t index) {
    if (static_cast<size_t>(vertex) >= of_vertex.size()) of_vertex.resize(static_cast<size_t>(vertex) + 1, -1);
    int64_t& cur = of_vertex[static_cast<size_t>(vertex)];
    if (cur == -1) cur = index;
    else if (cur >= 0 && cur != index && table[static_cast<size_t>(cur)] != table[static_cast<size_t>(index)]) {
      cur = -2;
      if (conflict_vertex < 0) conflict_vertex = vertex;
    }
  }
};

// A corner's vt or vn index (1-based or negative), range-checked against the table so far.
int64_t corner_index(LineReader& lines, std::string_view text, size_t count, int64_t face, const char* what) {
  int64_t idx;
  if (!parse_int(text, idx) || idx == 0)
    lines.fail("face " + std::to_string(face) + ": malformed " + what + " index " + quote(text));
  const int64_t i = idx > 0 ? idx - 1 : static_cast<int64_t>(count) + idx;
  if (i < 0 || i >= static_cast<int64_t>(count))
    lines.fail("face " + std::to_string(face) + " names " + what + " " + std::to_string(idx) + " but " +
               std::to_string(count) + " precede it");
  return i;
}

VertexProperty::Type property_type(std::string_view t) {
  using T = VertexProperty::Type;
  if (t == "float") return T::Float;
  if (t == "int") return T::Int;
  if (t == "char") return T::Int8;
  if (t == "uchar") return T::UInt8;
  if (t == "short") return T::Int16;
  if (t == "ushort") return T::UInt16;
  if (t == "uint") return T::UInt32;
  return T::Double;
}

// Moves per-vertex vt / vn (consistent ones) and the '#vp' block into `a`.
void keep_attributes(const Mesh& m, const std::string& name, CornerAttribute& vt, CornerAttribute& vn,
                     std::vector<VertexProperty>& block, int64_t block_rows, int64_t block_line, MeshAttributes& a) {
  const size_t nv = m.x.size();
  auto per_vertex = [&](CornerAttribute& c, std::initializer_list<const char*> names, const char* what) {
    if (c.table.empty()) return;
    c.of_vertex.resize(nv, -1);
    int64_t missing = -1;
    for (size_t v = 0; v < nv && missing < 0; ++v)
      if (c.of_vertex[v] == -1) missing = static_cast<int64_t>(v);
    if (c.conflict_vertex >= 0 || missing >= 0) {
      a.notes.push_back(name + ": " + what + " not kept per vertex: vertex " +
                        std::to_string(c.conflict_vertex >= 0 ? c.conflict_vertex : missing) +
                        (c.conflict_vertex >= 0 ? " has corners with different values (a seam)" : " has none"));
      return;
    }
    int k = 0;
    for (const char* n : names) {
      VertexProperty p{n, VertexProperty::Type::Double, std::vector<double>(nv)};
      for (size_t v = 0; v < nv; ++v) p.values[v] = c.table[static_cast<size_t>(c.of_vertex[v])][k];
      a.vertex.push_back(std::move(p));
      ++k;
    }
  };
  per_vertex(vt, {"u", "v"}, "texture coordinates (vt)");
  per_vertex(vn, {"nx", "ny", "nz"}, "normals (vn)");
  if (block.empty()) return;
  if (block_rows != static_cast<int64_t>(nv))
    fail_line(name, block_line, "the '#locus vertex-properties' block has " + std::to_string(block_rows) +
                                    " '#vp' rows for " + std::to_string(nv) + " vertices");
  for (VertexProperty& p : block) {
    // A block property replaces a vt / vn one of the same name (it is the writer's own copy).
    std::erase_if(a.vertex, [&](const VertexProperty& q) { return q.name == p.name; });
    a.vertex.push_back(std::move(p));
  }
}

// What the reader keeps between lines.
struct ObjState {
  Mesh m;
  std::vector<int32_t> face;
  std::vector<ForwardRef> forward;
  int64_t nf = 0;
  CornerAttribute vt, vn;
  std::vector<VertexProperty> block;  // the '#vp' block
  int64_t block_rows = 0, block_line = 0;
};

// "vt u v" / "vn x y z".
void read_corner_value(LineReader& lines, std::string_view kw, Fields& fields, ObjState& st) {
  CornerAttribute& table = kw == "vt" ? st.vt : st.vn;
  std::array<double, 3> c{0, 0, 0};
  const int want = kw == "vt" ? 2 : 3;
  for (int k = 0; k < want; ++k) {
    const std::string_view tok = fields.next();
    const char* last = tok.data() + tok.size();
    auto [ptr, ec] = std::from_chars(tok.data(), last, c[static_cast<size_t>(k)]);
    // nan is a value here: locus writes it for a vertex without UVs (outside a log map's patch).
    if (tok.empty() || ec != std::errc() || ptr != last)
      lines.fail(std::string(kw) + " " + std::to_string(table.table.size() + 1) + ": expected " +
                 std::to_string(want) + " numbers");
  }
  table.table.push_back(c);
}

// "#locus vertex-properties NAME:TYPE ..." (the keyword pair already read).
void read_block_header(LineReader& lines, Fields& fields, ObjState& st) {
  st.block.clear();
  st.block_rows = 0;
  st.block_line = lines.line_number();
  for (std::string_view tok = fields.next(); !tok.empty(); tok = fields.next()) {
    const size_t colon = tok.find(':');
    if (colon == std::string_view::npos || colon == 0) lines.fail("malformed property " + quote(tok) + " (expected NAME:TYPE)");
    st.block.push_back({std::string(tok.substr(0, colon)), property_type(tok.substr(colon + 1)), {}});
  }
}

// "#vp x y ...": one row of the block.
void read_block_row(LineReader& lines, Fields& fields, ObjState& st) {
  for (VertexProperty& p : st.block) {
    const std::string_view tok = fields.next();
    double x = 0;
    const char* last = tok.data() + tok.size();
    auto [ptr, ec] = std::from_chars(tok.data(), last, x);
    if (tok.empty() || ec != std::errc() || ptr != last)
      lines.fail("'#vp' row " + std::to_string(st.block_rows) + ": expected a number for " + p.name);
    p.values.push_back(x);
  }
  ++st.block_rows;
}

void read_vertex(LineReader& lines, Fields& fields, Mesh& m) {
  const int64_t v = static_cast<int64_t>(m.x.size());
  double c[3];
  for (int k = 0; k < 3; ++k) {
    const std::string_view tok = fields.next();
    if (tok.empty() || tok[0] == '#')
      lines.fail("vertex " + std::to_string(v) + " has " + std::to_string(k) + " coordinates (expected 3)");
    const std::string bad = parse_coordinate(tok, v, c[k]);
    if (!bad.empty()) lines.fail(bad);
  }
  // Anything after x y z (the optional w, or the r g b some exporters
  // append) is not part of the geometry and is ignored.
  const std::string bad = vertex_problem(v, c[0], c[1], c[2]);
  if (!bad.empty()) lines.fail(bad);
  if (v >= kMaxCount) lines.fail("more than " + std::to_string(kMaxCount) + " vertices");
  m.add_vertex(c[0], c[1], c[2]);
}

// One corner "v", "v/vt", "v//vn" or "v/vt/vn" of face st.nf: its vertex id
// (0-based), and with `attributes` its vt / vn.
int32_t read_corner(LineReader& lines, std::string_view tok, int64_t nv_now, bool attributes, ObjState& st) {
  const int64_t nf = st.nf;
  const size_t slash = tok.find('/');
  const std::string_view idx_text = tok.substr(0, slash);
  int64_t idx;
  if (!parse_int(idx_text, idx) || (slash != std::string_view::npos && !corner_tail_ok(tok.substr(slash))))
    lines.fail("face " + std::to_string(nf) + ": malformed corner " + quote(tok) +
               " (expected v, v/vt, v//vn or v/vt/vn)");
  int64_t vid = 0;
  if (idx > 0) {
    if (idx > kMaxCount)
      lines.fail("face " + std::to_string(nf) + " references vertex " + std::to_string(idx) +
                 " (1-based) but the file has " + std::to_string(nv_now) + " vertices so far");
    vid = idx - 1;
    if (idx > nv_now) st.forward.push_back({lines.line_number(), nf, idx});
  } else if (idx < 0) {
    vid = nv_now + idx;
    if (vid < 0)
      lines.fail("face " + std::to_string(nf) + " has relative index " + std::to_string(idx) + " but only " +
                 std::to_string(nv_now) + " vertices precede it (negative out of range)");
  } else {
    lines.fail("face " + std::to_string(nf) + " has vertex index 0 (OBJ indices start at 1)");
  }
  if (attributes && slash != std::string_view::npos) {
    const std::string_view rest = tok.substr(slash + 1);
    const size_t slash2 = rest.find('/');
    const std::string_view t_text = rest.substr(0, slash2);
    if (!t_text.empty()) st.vt.name(vid, corner_index(lines, t_text, st.vt.table.size(), nf, "vt"));
    if (slash2 != std::string_view::npos && slash2 + 1 < rest.size())
      st.vn.name(vid, corner_index(lines, rest.substr(slash2 + 1), st.vn.table.size(), nf, "vn"));
  }
  return static_cast<int32_t>(vid);
}

void read_face(LineReader& lines, Fields& fields, bool attributes, ObjState& st) {
  st.face.clear();
  const int64_t nv_now = static_cast<int64_t>(st.m.x.size());
  for (std::string_view tok = fields.next(); !tok.empty() && tok[0] != '#'; tok = fields.next())
    st.face.push_back(read_corner(lines, tok, nv_now, attributes, st));
  const std::string bad = face_problem(st.nf, st.face);
  if (!bad.empty()) lines.fail(bad);
  Mesh& m = st.m;
  if (st.nf >= kMaxCount || static_cast<int64_t>(m.face_vertices.size() + st.face.size()) > kMaxCount)
    lines.fail("more faces or face corners than a mesh can index (" + std::to_string(kMaxCount) + ")");
  m.face_vertices.insert(m.face_vertices.end(), st.face.begin(), st.face.end());
  m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
  ++st.nf;
}

}  // namespace

Mesh read_obj(std::string_view data, const std::string& name, const ReadOptions& opt, MeshAttributes* attributes) {
  (void)opt;  // OBJ has no header counts; read_mesh already bounded the file size by max_bytes
  LineReader lines(data, name);
  ObjState st;
  std::string_view line;
  while (lines.next(line)) {
    Fields fields(line);
    const std::string_view kw = fields.next();
    if (attributes && (kw == "vt" || kw == "vn"))
      read_corner_value(lines, kw, fields, st);
    else if (attributes && kw == "#locus" && fields.next() == "vertex-properties")
      read_block_header(lines, fields, st);
    else if (attributes && kw == "#vp" && !st.block.empty())
      read_block_row(lines, fields, st);
    else if (kw.size() == 1 && kw[0] == 'v')
      read_vertex(lines, fields, st.m);
    else if (kw.size() == 1 && kw[0] == 'f')
      read_face(lines, fields, attributes != nullptr, st);
    // Every other statement is ignored on purpose (see the top of the file).
  }

  Mesh& m = st.m;
  const int64_t nv = static_cast<int64_t>(m.x.size());
  for (const ForwardRef& r : st.forward)
    if (r.index > nv)
      fail_line(name, r.line,
                "face " + std::to_string(r.face) + " references vertex " + std::to_string(r.index) +
                    " (1-based) but the file has " + std::to_string(nv) + " vertices (index out of range)");
  finish_mesh(m, name);
  if (attributes) keep_attributes(m, name, st.vt, st.vn, st.block, st.block_rows, st.block_line, *attributes);
  return m;
}

}  // namespace locus::io
