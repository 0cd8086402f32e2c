// Stanford PLY reader (locus/mesh_io.hpp): ascii, binary_little_endian and
// binary_big_endian. Vertices come from element `vertex` (properties x, y, z
// of any scalar type, in any order among other properties); faces from element
// `face`, list property `vertex_indices` or `vertex_index` with any integer
// count and index types. Every other element and property (normals, colours,
// edges, materials, list properties such as texcoord) is skipped by its
// declared size, except that the vertex element's scalar properties are
// returned as MeshAttributes when asked. `comment` and `obj_info` lines are ignored. Not from the
// thesis: file plumbing.
//
// Hostile input: before anything is allocated, the header counts are checked
// against the bytes that follow (each binary element has a known minimum size,
// each ascii property needs at least one character and a separator) and
// against ReadOptions::max_bytes. Binary reads are bounds-checked against the
// buffer; errors name the byte offset and the element item, ascii errors the
// line.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "locus/io/mesh_checks.hpp"
#include "locus/io/readers.hpp"
#include "locus/io/text_scanner.hpp"

namespace locus::io {

namespace {

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

size_t type_size(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 1;
}

bool parse_type(std::string_view s, Type& t) {
  if (s == "char" || s == "int8") t = Type::I8;
  else if (s == "uchar" || s == "uint8") t = Type::U8;
  else if (s == "short" || s == "int16") t = Type::I16;
  else if (s == "ushort" || s == "uint16") t = Type::U16;
  else if (s == "int" || s == "int32") t = Type::I32;
  else if (s == "uint" || s == "uint32") t = Type::U32;
  else if (s == "float" || s == "float32") t = Type::F32;
  else if (s == "double" || s == "float64") t = Type::F64;
  else return false;
  return true;
}

bool is_integer(Type t) { return t != Type::F32 && t != Type::F64; }

struct Property {
  std::string name;
  Type type = Type::F32;   // value type (list items for a list)
  bool list = false;
  Type count_type = Type::U8;
};

struct Element {
  std::string name;
  int64_t count = 0;
  std::vector<Property> props;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

// What the body reader needs to know about the two elements we keep.
struct Layout {
  int vertex_elem = -1, face_elem = -1;
  int px = -1, py = -1, pz = -1;  // property indices of x, y, z in the vertex element
  int pface = -1;                 // property index of the face index list
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  Layout layout;
  size_t body_offset = 0;
};

Header parse_header(std::string_view data, const std::string& name) {
  LineReader lines(data, name);
  std::string_view line;
  bool magic = lines.next(line);
  if (magic) {
    Fields f(line);
    magic = f.next() == "ply" && f.done();
  }
  if (!magic)
    fail(ErrorCode::BadInput, name + ": not a PLY file (the first line is not 'ply')");
  Header h;
  bool have_format = false;
  for (;;) {
    if (!lines.next(line))
      fail_line(name, lines.line_number(), "the file ends inside the PLY header (truncated: no end_header)");
    Fields f(line);
    const std::string_view kw = f.next();
    if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") break;
    if (kw == "format") {
      const std::string_view fmt = f.next();
      if (fmt == "ascii") h.format = Format::Ascii;
      else if (fmt == "binary_little_endian") h.format = Format::BinaryLE;
      else if (fmt == "binary_big_endian") h.format = Format::BinaryBE;
      else lines.fail("unknown PLY format " + quote(fmt) + " (expected ascii, binary_little_endian or binary_big_endian)");
      have_format = true;
    } else if (kw == "element") {
      Element e;
      e.name = std::string(f.next());
      const std::string_view ctok = f.next();
      if (e.name.empty() || ctok.empty()) lines.fail("element line needs a name and a count");
      if (!parse_int(ctok, e.count) || e.count < 0)
        lines.fail("element " + quote(e.name) + " has an invalid count " + quote(ctok) +
                   " (not a non-negative 64-bit integer: overflow or garbage)");
      // Only the two elements we keep must be unique; checking every name
      // against every other would be quadratic in a hostile header.
      if (e.name == "vertex" || e.name == "face")
        for (const Element& o : h.elements)
          if (o.name == e.name) lines.fail("element '" + e.name + "' is declared twice");
      h.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (h.elements.empty()) lines.fail("property declared before any element");
      Element& e = h.elements.back();
      Property p;
      std::string_view t = f.next();
      if (t == "list") {
        p.list = true;
        const std::string_view ct = f.next();
        if (!parse_type(ct, p.count_type) || !is_integer(p.count_type))
          lines.fail("list count type " + quote(ct) + " is not an integer PLY type");
        t = f.next();
      }
      if (!parse_type(t, p.type)) lines.fail("unknown PLY property type " + quote(t));
      p.name = std::string(f.next());
      if (p.name.empty()) lines.fail("property without a name");
      const int idx = static_cast<int>(e.props.size());
      Layout& L = h.layout;
      auto claim = [&](int& slot) {
        if (slot >= 0) lines.fail("property '" + p.name + "' appears twice in element '" + e.name + "'");  // names are x/y/z/vertex_indices here
        slot = idx;
      };
      const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
      if (is_vertex && (p.name == "x" || p.name == "y" || p.name == "z")) {
        if (p.list) lines.fail("vertex property '" + p.name + "' must be a scalar, not a list");
        claim(p.name == "x" ? L.px : p.name == "y" ? L.py : L.pz);
      }
      if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!p.list) lines.fail("face property '" + p.name + "' must be a list");
        if (!is_integer(p.type)) lines.fail("face property '" + p.name + "' must hold integers");
        claim(L.pface);
      }
      e.props.push_back(std::move(p));
    } else {
      lines.fail("unknown PLY header line " + quote(kw));
    }
  }
  if (!have_format) fail(ErrorCode::BadInput, name + ": the PLY header has no 'format' line");
  for (size_t i = 0; i < h.elements.size(); ++i) {
    if (h.elements[i].name == "vertex") h.layout.vertex_elem = static_cast<int>(i);
    if (h.elements[i].name == "face") h.layout.face_elem = static_cast<int>(i);
  }
  const Layout& L = h.layout;
  if (L.vertex_elem < 0) fail(ErrorCode::BadInput, name + ": the PLY header declares no 'vertex' element");
  if (L.px < 0 || L.py < 0 || L.pz < 0)
    fail(ErrorCode::BadInput, name + ": element 'vertex' lacks one of the properties x, y, z");
  if (L.face_elem >= 0 && L.pface < 0 && !h.elements[L.face_elem].props.empty())
    fail(ErrorCode::BadInput, name + ": element 'face' has no list property 'vertex_indices' or 'vertex_index'");
  h.body_offset = static_cast<size_t>(lines.position() - data.data());
  return h;
}

// Refuses counts the body cannot hold, and counts past the memory budget,
// before anything is allocated.
void check_counts(const Header& h, uint64_t body_bytes, const std::string& name, const ReadOptions& opt) {
  const uint64_t at = h.body_offset;
  uint64_t need = 0;
  for (const Element& e : h.elements) {
    uint64_t per = 0;
    for (const Property& p : e.props)
      per += h.format == Format::Ascii ? 2 : type_size(p.list ? p.count_type : p.type);
    need = sat_add(need, sat_mul(uint64_t(e.count), per));
  }
  const uint64_t avail = h.format == Format::Ascii ? body_bytes + 1 : body_bytes;  // last ascii value may lack a newline
  if (need > avail)
    fail_offset(name, at, "the PLY header counts need at least " + std::to_string(need) + " bytes of data but only " +
                              std::to_string(body_bytes) + " follow the header (truncated file or corrupt counts)");
  const int64_t nv = h.elements[h.layout.vertex_elem].count;
  const int64_t nf = h.layout.face_elem >= 0 ? h.elements[h.layout.face_elem].count : 0;
  if (nv > kMaxCount || nf > kMaxCount)
    fail_offset(name, at, std::to_string(nv) + " vertices / " + std::to_string(nf) +
                              " faces exceed what a mesh can index (" + std::to_string(kMaxCount) + ")");
  check_budget(name, uint64_t(nv), uint64_t(nf), 3 * uint64_t(nf), opt);
}

// ---- binary body ----

class BinaryBody {
 public:
  BinaryBody(std::string_view data, size_t pos, bool swap, const std::string& name)
      : p_(reinterpret_cast<const unsigned char*>(data.data())), size_(data.size()), pos_(pos), swap_(swap),
        name_(name) {}

  size_t pos() const { return pos_; }
  [[noreturn]] void fail_here(size_t at, const Element& e, int64_t item, const std::string& msg) const {
    fail_offset(name_, at, "element " + quote(e.name) + " item " + std::to_string(item) + ": " + msg);
  }
  // Makes sure n more bytes exist (n may be huge for hostile list counts).
  void need(uint64_t n, const Element& e, int64_t item) const {
    if (n > size_ - pos_)
      fail_here(pos_, e, item, "the file ends here but " + std::to_string(n) + " more bytes are needed (truncated)");
  }
  void skip(uint64_t n) { pos_ += static_cast<size_t>(n); }

  template <class U>
  U load() {
    U u;
    std::memcpy(&u, p_ + pos_, sizeof(U));
    pos_ += sizeof(U);
    if (swap_) {
      if constexpr (sizeof(U) == 2) u = std::bit_cast<U>(__builtin_bswap16(std::bit_cast<uint16_t>(u)));
      if constexpr (sizeof(U) == 4) u = std::bit_cast<U>(__builtin_bswap32(std::bit_cast<uint32_t>(u)));
      if constexpr (sizeof(U) == 8) u = std::bit_cast<U>(__builtin_bswap64(std::bit_cast<uint64_t>(u)));
    }
    return u;
  }
  // Reads one value of type t (bounds already checked by need()).
  double as_double(Type t) {
    switch (t) {
      case Type::I8: return load<int8_t>();
      case Type::U8: return load<uint8_t>();
      case Type::I16: return load<int16_t>();
      case Type::U16: return load<uint16_t>();
      case Type::I32: return load<int32_t>();
      case Type::U32: return load<uint32_t>();
      case Type::F32: return load<float>();
      case Type::F64: return load<double>();
    }
    return 0;
  }
  int64_t as_int(Type t) {  // t is an integer type
    switch (t) {
      case Type::I8: return load<int8_t>();
      case Type::U8: return load<uint8_t>();
      case Type::I16: return load<int16_t>();
      case Type::U16: return load<uint16_t>();
      case Type::I32: return load<int32_t>();
      case Type::U32: return load<uint32_t>();
      default: return 0;
    }
  }

 private:
  const unsigned char* p_;
  size_t size_;
  size_t pos_;
  bool swap_;
  const std::string& name_;
};

// The vertex element's scalar properties other than x, y, z, as attributes to
// fill (attr_of[property] = index in attrs->vertex, or -1).
std::vector<int> prepare_attributes(const Header& h, MeshAttributes* attrs) {
  const Layout& L = h.layout;
  const Element& e = h.elements[L.vertex_elem];
  std::vector<int> attr_of(e.props.size(), -1);
  if (!attrs) return attr_of;
  attrs->float_positions = L.px >= 0 && e.props[L.px].type == Type::F32;
  for (size_t pi = 0; pi < e.props.size(); ++pi) {
    const Property& p = e.props[pi];
    if (p.list || int(pi) == L.px || int(pi) == L.py || int(pi) == L.pz) continue;
    using VT = VertexProperty::Type;
    static constexpr VT kTypes[] = {VT::Int8, VT::UInt8, VT::Int16, VT::UInt16, VT::Int, VT::UInt32, VT::Float, VT::Double};
    attr_of[pi] = static_cast<int>(attrs->vertex.size());
    attrs->vertex.push_back({p.name, kTypes[static_cast<int>(p.type)], {}});
    attrs->vertex.back().values.reserve(static_cast<size_t>(e.count));
  }
  return attr_of;
}

void read_binary_body(std::string_view data, const Header& h, const std::string& name, Mesh& m, MeshAttributes* attrs) {
  const std::vector<int> attr_of = prepare_attributes(h, attrs);
  const bool file_le = h.format == Format::BinaryLE;
  const bool swap = file_le != (std::endian::native == std::endian::little);
  BinaryBody in(data, h.body_offset, swap, name);
  const Layout& L = h.layout;
  const int64_t nv = h.elements[L.vertex_elem].count;
  std::vector<int32_t> face;
  for (size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    if (e.props.empty()) continue;  // nothing to read, whatever the count
    const bool is_vertex = static_cast<int>(ei) == L.vertex_elem;
    const bool is_face = static_cast<int>(ei) == L.face_elem;
    uint64_t fixed = 0;  // bytes of an item when it has no lists
    bool has_list = false;
    for (const Property& p : e.props) {
      fixed += type_size(p.type);
      has_list |= p.list;
    }
    for (int64_t item = 0; item < e.count; ++item) {
      const size_t start = in.pos();
      if (!has_list) in.need(fixed, e, item);
      double c[3] = {0, 0, 0};
      for (size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (!p.list) {
          if (has_list) in.need(type_size(p.type), e, item);
          if (is_vertex && (int(pi) == L.px || int(pi) == L.py || int(pi) == L.pz)) {
            c[int(pi) == L.px ? 0 : int(pi) == L.py ? 1 : 2] = in.as_double(p.type);
          } else if (is_vertex && attr_of[pi] >= 0) {
            attrs->vertex[attr_of[pi]].values.push_back(in.as_double(p.type));
          } else {
            in.skip(type_size(p.type));
          }
          continue;
        }
        in.need(type_size(p.count_type), e, item);
        const size_t count_at = in.pos();
        const int64_t cnt = in.as_int(p.count_type);
        if (cnt < 0) in.fail_here(count_at, e, item, "negative list count " + std::to_string(cnt) + " for property " + quote(p.name));
        const uint64_t bytes = uint64_t(cnt) * type_size(p.type);  // cnt < 2^32, no overflow
        in.need(bytes, e, item);
        if (!(is_face && int(pi) == L.pface)) {
          in.skip(bytes);
          continue;
        }
        if (cnt < 3)
          in.fail_here(start, e, item, "face " + std::to_string(item) + " has " + std::to_string(cnt) + " vertices (a face needs at least 3)");
        face.clear();
        for (int64_t j = 0; j < cnt; ++j) {
          const int64_t idx = in.as_int(p.type);
          if (idx < 0 || idx >= nv)
            in.fail_here(start, e, item, "face " + std::to_string(item) + " references vertex " + std::to_string(idx) +
                                             " but the file has " + std::to_string(nv) + " vertices (index out of range)");
          face.push_back(static_cast<int32_t>(idx));
        }
      }
      if (is_vertex) {
        const std::string bad = vertex_problem(item, c[0], c[1], c[2]);
        if (!bad.empty()) in.fail_here(start, e, item, bad);
        m.add_vertex(c[0], c[1], c[2]);
      } else if (is_face && L.pface >= 0) {
        const std::string bad = face_problem(item, face);
        if (!bad.empty()) in.fail_here(start, e, item, bad);
        if (static_cast<int64_t>(m.face_vertices.size() + face.size()) > kMaxCount)
          in.fail_here(start, e, item, "more face corners than a mesh can index");
        m.face_vertices.insert(m.face_vertices.end(), face.begin(), face.end());
        m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
      }
    }
  }
}

// ---- ascii body ----

// The ascii body is a stream of whitespace-separated values; most writers put
// one element per line, but the format does not require it, so tokens are
// taken across lines while the line number is kept for messages.
class TokenStream {
 public:
  TokenStream(std::string_view body, const std::string& name, int64_t first_line)
      : lines_(body, name), fields_(std::string_view()), name_(name), base_(first_line - 1) {}
  std::string_view next() {
    for (;;) {
      const std::string_view t = fields_.next();
      if (!t.empty()) return t;
      std::string_view line;
      if (!lines_.next(line)) return {};
      fields_ = Fields(line);
    }
  }
  int64_t line() const { return base_ + lines_.line_number(); }
  [[noreturn]] void fail(const std::string& msg) const { fail_line(name_, line(), msg); }

 private:
  LineReader lines_;
  Fields fields_;
  const std::string& name_;
  int64_t base_;
};

void read_ascii_body(std::string_view data, const Header& h, const std::string& name, Mesh& m, MeshAttributes* attrs) {
  const std::vector<int> attr_of = prepare_attributes(h, attrs);
  // Line number of the first body line, for messages.
  int64_t header_lines = 0;
  for (size_t i = 0; i < h.body_offset; ++i) header_lines += data[i] == '\n';
  TokenStream in(data.substr(h.body_offset), name, header_lines + 1);
  const Layout& L = h.layout;
  const int64_t nv = h.elements[L.vertex_elem].count;
  std::vector<int32_t> face;
  for (size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    if (e.props.empty()) continue;
    const bool is_vertex = static_cast<int>(ei) == L.vertex_elem;
    const bool is_face = static_cast<int>(ei) == L.face_elem;
    for (int64_t item = 0; item < e.count; ++item) {
      auto take = [&](const Property& p) {
        const std::string_view t = in.next();
        if (t.empty())
          in.fail("the file ends inside element " + quote(e.name) + " item " + std::to_string(item) + " (property " +
                  quote(p.name) + "): truncated");
        return t;
      };
      double c[3] = {0, 0, 0};
      for (size_t pi = 0; pi < e.props.size(); ++pi) {
        const Property& p = e.props[pi];
        if (!p.list) {
          const std::string_view t = take(p);
          if (is_vertex && (int(pi) == L.px || int(pi) == L.py || int(pi) == L.pz)) {
            const std::string bad = parse_coordinate(t, item, c[int(pi) == L.px ? 0 : int(pi) == L.py ? 1 : 2]);
            if (!bad.empty()) in.fail(bad);
          } else if (is_vertex && attr_of[pi] >= 0) {
            double v = 0;
            if (!parse_double(t, v))
              in.fail("vertex " + std::to_string(item) + ": property " + quote(p.name) + " is not a number: " + quote(t));
            attrs->vertex[attr_of[pi]].values.push_back(v);
          }
          continue;
        }
        const std::string_view ct = take(p);
        int64_t cnt;
        if (!parse_int(ct, cnt))
          in.fail("element " + quote(e.name) + " item " + std::to_string(item) + ": list count of " + quote(p.name) +
                  " is not an integer: " + quote(ct));
        if (cnt < 0)
          in.fail("element " + quote(e.name) + " item " + std::to_string(item) + ": negative list count " +
                  std::to_string(cnt) + " for property " + quote(p.name));
        const bool keep = is_face && int(pi) == L.pface;
        if (keep && cnt < 3)
          in.fail("face " + std::to_string(item) + " has " + std::to_string(cnt) + " vertices (a face needs at least 3)");
        if (keep) face.clear();
        // Each value needs a token, so a huge count ends in "truncated" after
        // at most the file's worth of tokens: no allocation from the count.
        for (int64_t j = 0; j < cnt; ++j) {
          const std::string_view t = take(p);
          if (!keep) continue;
          int64_t idx;
          if (!parse_int(t, idx)) in.fail("face " + std::to_string(item) + ": expected a vertex index, found " + quote(t));
          if (idx < 0 || idx >= nv)
            in.fail("face " + std::to_string(item) + " references vertex " + std::to_string(idx) + " but the file has " +
                    std::to_string(nv) + " vertices (index out of range)");
          face.push_back(static_cast<int32_t>(idx));
        }
      }
      if (is_vertex) {
        const std::string bad = vertex_problem(item, c[0], c[1], c[2]);
        if (!bad.empty()) in.fail(bad);
        m.add_vertex(c[0], c[1], c[2]);
      } else if (is_face && L.pface >= 0) {
        const std::string bad = face_problem(item, face);
        if (!bad.empty()) in.fail(bad);
        if (static_cast<int64_t>(m.face_vertices.size() + face.size()) > kMaxCount)
          in.fail("more face corners than a mesh can index");
        m.face_vertices.insert(m.face_vertices.end(), face.begin(), face.end());
        m.face_offsets.push_back(static_cast<int32_t>(m.face_vertices.size()));
      }
    }
  }
}

}  // namespace

Mesh read_ply(std::string_view data, const std::string& name, const ReadOptions& opt, MeshAttributes* attributes) {
  const Header h = parse_header(data, name);
  check_counts(h, data.size() - h.body_offset, name, opt);
  const int64_t nv = h.elements[h.layout.vertex_elem].count;
  const int64_t nf = h.layout.face_elem >= 0 ? h.elements[h.layout.face_elem].count : 0;
  Mesh m;
  m.x.reserve(nv); m.y.reserve(nv); m.z.reserve(nv);
  m.face_offsets.reserve(nf + 1);
  m.face_vertices.reserve(3 * nf);
  if (h.format == Format::Ascii) read_ascii_body(data, h, name, m, attributes);
  else read_binary_body(data, h, name, m, attributes);
  finish_mesh(m, name);
  return m;
}

}  // namespace locus::io
