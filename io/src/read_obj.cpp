// Wavefront OBJ reader (locus/mesh_io.hpp): `v x y z [w]` vertices and `f`
// polygon faces with corners written `v`, `v/vt`, `v//vn` or `v/vt/vn`,
// positive (1-based) or negative (relative to the vertices read so far)
// indices. Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...),
// comments and blank lines are ignored. Not from the thesis: file plumbing.
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

}  // namespace

Mesh read_obj(std::string_view data, const std::string& name, const ReadOptions& opt) {
  (void)opt;  // OBJ has no header counts; read_mesh already bounded the file size by max_bytes
  LineReader lines(data, name);
  Mesh m;
  std::vector<int32_t> face;
  std::vector<ForwardRef> forward;
  int64_t nf = 0;

  std::string_view line;
  while (lines.next(line)) {
    Fields fields(line);
    const std::string_view kw = fields.next();
    if (kw.size() == 1 && kw[0] == 'v') {
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
    } else if (kw.size() == 1 && kw[0] == 'f') {
      face.clear();
      const int64_t nv_now = static_cast<int64_t>(m.x.size());
      for (std::string_view tok = fields.next(); !tok.empty() && tok[0] != '#'; tok = fields.next()) {
        const size_t slash = tok.find('/');
        const std::string_view idx_text = tok.substr(0, slash);
        int64_t idx;
        if (!parse_int(idx_text, idx) || (slash != std::string_view::npos && !corner_tail_ok(tok.substr(slash))))
          lines.fail("face " + std::to_string(nf) + ": malformed corner " + quote(tok) +
                     " (expected v, v/vt, v//vn or v/vt/vn)");
        int64_t vid;
        if (idx > 0) {
          if (idx > kMaxCount)
            lines.fail("face " + std::to_string(nf) + " references vertex " + std::to_string(idx) +
                       " (1-based) but the file has " + std::to_string(nv_now) + " vertices so far");
          vid = idx - 1;
          if (idx > nv_now) forward.push_back({lines.line_number(), nf, idx});
        } else if (idx < 0) {
          vid = nv_now + idx;
          if (vid < 0)
            lines.fail("face " + std::to_string(nf) + " has relative index " + std::to_string(idx) +
                       " but only " + std::to_string(nv_now) + " vertices precede it (negative out of range)");
        } else {
          lines.fail("face " + std::to_string(nf) + " has vertex index 0 (OBJ indices start at 1)");
        }
        face.push_back(static_cast<int32_t>(vid));
      }
      const std::string bad = face_problem(nf, face);
      if (!bad.empty()) lines.fail(bad);
      if (nf >= kMaxCount || static_cast<int64_t>(m.face_vertices.size() + face.size()) > kMaxCount)
        lines.fail("more faces or face corners than a mesh can index (" + std::to_string(kMaxCount) + ")");
      m.face_vertices.insert(m.face_vertices.end(), face.begin(), face.end());
      m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
      ++nf;
    }
    // Every other statement is ignored on purpose (see the top of the file).
  }

  const int64_t nv = static_cast<int64_t>(m.x.size());
  for (const ForwardRef& r : forward)
    if (r.index > nv)
      fail_line(name, r.line,
                "face " + std::to_string(r.face) + " references vertex " + std::to_string(r.index) +
                    " (1-based) but the file has " + std::to_string(nv) + " vertices (index out of range)");
  finish_mesh(m, name);
  return m;
}

}  // namespace locus::io
