// write_mesh (locus/mesh_io.hpp): PLY (binary little endian by default, or
// ascii) with named per-vertex properties and u/v texture coordinates; OBJ
// (with `vt` and `f a/a b/b c/c` corners when uv is given); OFF. The format
// follows the extension. Not from the thesis: file plumbing.
//
// Exact round trips: coordinates are written as double in binary PLY, and in
// the text formats with std::to_chars' shortest representation, which is
// guaranteed to parse back to the same double (the same bits as printing
// max_digits10 digits, usually fewer characters). OBJ has no slot for named
// vertex properties: they go to a comment block after the faces; OFF shows the
// first one as vertex colours; OFF has no uv (refused).
//
// The whole file is built in memory and written atomically
// (io/atomic_file_write.hpp: temporary + fsync + rename). Caller
// mistakes (inconsistent mesh arrays, property arrays of the wrong length,
// non-finite coordinates that no reader would accept back) are
// ErrorCode::BadUsage naming what is wrong.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cerrno>
#include <string>
#include <vector>

#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

namespace locus {

namespace {

using io::lower_extension;

[[noreturn]] void usage(const std::string& path, const std::string& msg) {
  fail(ErrorCode::BadUsage, "write_mesh " + path + ": " + msg);
}

const char* ply_type(VertexProperty::Type t) {
  switch (t) {
    case VertexProperty::Type::Float: return "float";
    case VertexProperty::Type::Double: return "double";
    case VertexProperty::Type::Int: return "int";
    case VertexProperty::Type::Int8: return "char";
    case VertexProperty::Type::UInt8: return "uchar";
    case VertexProperty::Type::Int16: return "short";
    case VertexProperty::Type::UInt16: return "ushort";
    case VertexProperty::Type::UInt32: return "uint";
  }
  return "double";
}

bool is_integer(VertexProperty::Type t) { return t != VertexProperty::Type::Float && t != VertexProperty::Type::Double; }

size_t type_bytes(VertexProperty::Type t) {
  switch (t) {
    case VertexProperty::Type::Double: return 8;
    case VertexProperty::Type::Int8: case VertexProperty::Type::UInt8: return 1;
    case VertexProperty::Type::Int16: case VertexProperty::Type::UInt16: return 2;
    default: return 4;
  }
}

// The value range of an integer type, for validation.
std::pair<double, double> int_range(VertexProperty::Type t) {
  switch (t) {
    case VertexProperty::Type::Int8: return {-128.0, 127.0};
    case VertexProperty::Type::UInt8: return {0.0, 255.0};
    case VertexProperty::Type::Int16: return {-32768.0, 32767.0};
    case VertexProperty::Type::UInt16: return {0.0, 65535.0};
    case VertexProperty::Type::UInt32: return {0.0, 4294967295.0};
    default: return {-2147483648.0, 2147483647.0};
  }
}

void validate(const std::string& path, const Mesh& m, const WriteOptions& opt) {
  const size_t nv = m.x.size();
  if (m.y.size() != nv || m.z.size() != nv) usage(path, "x, y, z have different lengths");
  if (m.face_offsets.empty() || m.face_offsets[0] != 0) usage(path, "face_offsets must start with 0");
  const int64_t nf = static_cast<int64_t>(m.face_offsets.size()) - 1;
  for (int64_t f = 0; f < nf; ++f)
    if (int64_t(m.face_offsets[f + 1]) < int64_t(m.face_offsets[f]) + 1)
      usage(path, "face_offsets decrease or give face " + std::to_string(f) + " no vertex");
  if (static_cast<size_t>(m.face_offsets.back()) != m.face_vertices.size())
    usage(path, "face_offsets end at " + std::to_string(m.face_offsets.back()) + " but face_vertices has " +
                    std::to_string(m.face_vertices.size()) + " entries");
  for (size_t i = 0; i < m.face_vertices.size(); ++i)
    if (m.face_vertices[i] < 0 || static_cast<size_t>(m.face_vertices[i]) >= nv)
      usage(path, "a face references vertex " + std::to_string(m.face_vertices[i]) + " but the mesh has " +
                      std::to_string(nv) + " vertices");
  for (size_t v = 0; v < nv; ++v)
    if (!std::isfinite(m.x[v]) || !std::isfinite(m.y[v]) || !std::isfinite(m.z[v]))
      usage(path, "vertex " + std::to_string(v) + " has a non-finite coordinate (no reader would accept the file)");
  if (opt.uv && opt.uv->size() != 2 * nv)
    usage(path, "uv has " + std::to_string(opt.uv->size()) + " values, expected 2 * " + std::to_string(nv));
  for (const VertexProperty& p : opt.vertex_properties) {
    if (p.name.empty()) usage(path, "a vertex property has no name");
    for (char c : p.name)
      if (c <= ' ' || c > '~') usage(path, "vertex property name '" + p.name + "' must be printable without spaces");
    if (p.name == "x" || p.name == "y" || p.name == "z" || (opt.uv && (p.name == "u" || p.name == "v")))
      usage(path, "vertex property name '" + p.name + "' clashes with a built-in property");
    if (p.values.size() != nv)
      usage(path, "vertex property '" + p.name + "' has " + std::to_string(p.values.size()) + " values, expected " +
                      std::to_string(nv));
    if (is_integer(p.type)) {
      const auto [lo, hi] = int_range(p.type);
      for (size_t v = 0; v < nv; ++v)
        if (!(p.values[v] == std::trunc(p.values[v]) && p.values[v] >= lo && p.values[v] <= hi))
          usage(path, std::string(ply_type(p.type)) + " vertex property '" + p.name +
                          "' has a non-integer or out-of-range value at vertex " + std::to_string(v));
    }
  }
}

void put_num(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  out.append(buf, r.ptr);
}
void put_num(std::string& out, float v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}
void put_num(std::string& out, int64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

// Appends v in little-endian byte order whatever the host.
template <class T>
void put_le(std::string& out, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    if constexpr (sizeof(T) == 2) v = std::bit_cast<T>(__builtin_bswap16(std::bit_cast<uint16_t>(v)));
    if constexpr (sizeof(T) == 4) v = std::bit_cast<T>(__builtin_bswap32(std::bit_cast<uint32_t>(v)));
    if constexpr (sizeof(T) == 8) v = std::bit_cast<T>(__builtin_bswap64(std::bit_cast<uint64_t>(v)));
  }
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

void put_property_le(std::string& out, VertexProperty::Type t, double v) {
  switch (t) {
    case VertexProperty::Type::Float: put_le(out, static_cast<float>(v)); break;
    case VertexProperty::Type::Double: put_le(out, v); break;
    case VertexProperty::Type::Int: put_le(out, static_cast<int32_t>(v)); break;
    case VertexProperty::Type::Int8: put_le(out, static_cast<int8_t>(v)); break;
    case VertexProperty::Type::UInt8: put_le(out, static_cast<uint8_t>(v)); break;
    case VertexProperty::Type::Int16: put_le(out, static_cast<int16_t>(v)); break;
    case VertexProperty::Type::UInt16: put_le(out, static_cast<uint16_t>(v)); break;
    case VertexProperty::Type::UInt32: put_le(out, static_cast<uint32_t>(v)); break;
  }
}

void put_property_text(std::string& out, VertexProperty::Type t, double v) {
  if (is_integer(t)) put_num(out, static_cast<int64_t>(v));
  else if (t == VertexProperty::Type::Float) put_num(out, static_cast<float>(v));
  else put_num(out, v);
}

// OBJ has no vertex properties: they follow the faces as a comment block every
// OBJ reader skips (documented in README "Output formats"):
//   #locus vertex-properties NAME:TYPE ...
//   #vp VALUE ...        (one line per vertex, in vertex order; nan for none)
void append_obj_properties(std::string& out, const std::vector<VertexProperty>& props, size_t nv) {
  if (props.empty()) return;
  out += "#locus vertex-properties";
  for (const VertexProperty& p : props) out += " " + p.name + ":" + ply_type(p.type);
  out += '\n';
  for (size_t v = 0; v < nv; ++v) {
    out += "#vp";
    for (const VertexProperty& p : props) {
      out += ' ';
      put_property_text(out, p.type, p.values[v]);
    }
    out += '\n';
  }
}

// Viridis-like ramp (five anchors, linear between) for OFF colours.
std::array<uint8_t, 3> scalar_colour(double value, double lo, double hi) {
  if (!std::isfinite(value)) return {128, 128, 128};
  static const double anchors[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  const double s = hi > lo ? std::clamp((value - lo) / (hi - lo), 0.0, 1.0) * 4.0 : 0.0;
  const int k = std::min(3, static_cast<int>(s));
  const double w = s - k;
  std::array<uint8_t, 3> c{};
  for (int i = 0; i < 3; ++i) c[i] = static_cast<uint8_t>(std::lround(anchors[k][i] * (1 - w) + anchors[k + 1][i] * w));
  return c;
}

std::string ply(const Mesh& m, const WriteOptions& opt) {
  const size_t nv = m.x.size();
  const int64_t nf = m.num_faces();
  int32_t max_degree = 0;
  for (int64_t f = 0; f < nf; ++f) max_degree = std::max(max_degree, m.face_offsets[f + 1] - m.face_offsets[f]);
  const bool uchar_count = max_degree <= 255;

  std::string out;
  out += "ply\nformat ";
  out += opt.binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  const char* pos_type = opt.float_positions ? "float" : "double";
  out += "comment written by locus\nelement vertex " + std::to_string(nv) + "\nproperty " + pos_type + " x\nproperty " +
         pos_type + " y\nproperty " + pos_type + " z\n";
  if (opt.uv) out += "property double u\nproperty double v\n";
  for (const VertexProperty& p : opt.vertex_properties)
    out += std::string("property ") + ply_type(p.type) + " " + p.name + "\n";
  out += "element face " + std::to_string(nf) + "\nproperty list " + (uchar_count ? "uchar" : "int") +
         " int vertex_indices\nend_header\n";

  if (opt.binary) {
    size_t vbytes = (opt.float_positions ? 12 : 24) + (opt.uv ? 16 : 0);
    for (const VertexProperty& p : opt.vertex_properties) vbytes += type_bytes(p.type);
    out.reserve(out.size() + nv * vbytes + nf * (uchar_count ? 1 : 4) + m.face_vertices.size() * 4);
    for (size_t v = 0; v < nv; ++v) {
      if (opt.float_positions) {
        put_le(out, static_cast<float>(m.x[v])); put_le(out, static_cast<float>(m.y[v])); put_le(out, static_cast<float>(m.z[v]));
      } else {
        put_le(out, m.x[v]); put_le(out, m.y[v]); put_le(out, m.z[v]);
      }
      if (opt.uv) { put_le(out, (*opt.uv)[2 * v]); put_le(out, (*opt.uv)[2 * v + 1]); }
      for (const VertexProperty& p : opt.vertex_properties) put_property_le(out, p.type, p.values[v]);
    }
    for (int64_t f = 0; f < nf; ++f) {
      const int32_t k = m.face_offsets[f + 1] - m.face_offsets[f];
      if (uchar_count) put_le(out, static_cast<uint8_t>(k));
      else put_le(out, k);
      for (int32_t j = 0; j < k; ++j) put_le(out, m.face_vertices[m.face_offsets[f] + j]);
    }
    return out;
  }

  for (size_t v = 0; v < nv; ++v) {
    if (opt.float_positions) {
      put_num(out, static_cast<float>(m.x[v])); out += ' '; put_num(out, static_cast<float>(m.y[v])); out += ' ';
      put_num(out, static_cast<float>(m.z[v]));
    } else {
      put_num(out, m.x[v]); out += ' '; put_num(out, m.y[v]); out += ' '; put_num(out, m.z[v]);
    }
    if (opt.uv) { out += ' '; put_num(out, (*opt.uv)[2 * v]); out += ' '; put_num(out, (*opt.uv)[2 * v + 1]); }
    for (const VertexProperty& p : opt.vertex_properties) {
      out += ' ';
      put_property_text(out, p.type, p.values[v]);
    }
    out += '\n';
  }
  for (int64_t f = 0; f < nf; ++f) {
    const int32_t k = m.face_offsets[f + 1] - m.face_offsets[f];
    put_num(out, int64_t(k));
    for (int32_t j = 0; j < k; ++j) { out += ' '; put_num(out, int64_t(m.face_vertices[m.face_offsets[f] + j])); }
    out += '\n';
  }
  return out;
}

// OBJ's own slots first: texture coordinates as vt (the result's UVs, else
// vertex properties u and v) and normals as vn (properties nx ny nz), one per
// vertex with the vertex's index; the other properties go to the '#vp' block.
std::string obj(const Mesh& m, const WriteOptions& opt) {
  std::string out = "# written by locus\n";
  const size_t nv = m.x.size();
  auto find = [&](const char* n) -> const VertexProperty* {
    for (const VertexProperty& p : opt.vertex_properties)
      if (p.name == n && p.values.size() == nv) return &p;
    return nullptr;
  };
  const VertexProperty *pu = find("u"), *pv = find("v");
  const VertexProperty *pnx = find("nx"), *pny = find("ny"), *pnz = find("nz");
  const bool prop_uv = !opt.uv && pu && pv;
  const bool has_vt = opt.uv || prop_uv;
  const bool has_vn = pnx && pny && pnz;
  std::vector<VertexProperty> rest;
  for (const VertexProperty& p : opt.vertex_properties) {
    const bool in_vt = prop_uv && (&p == pu || &p == pv);
    const bool in_vn = has_vn && (&p == pnx || &p == pny || &p == pnz);
    if (!in_vt && !in_vn) rest.push_back(p);
  }
  for (size_t v = 0; v < nv; ++v) {
    out += "v "; put_num(out, m.x[v]); out += ' '; put_num(out, m.y[v]); out += ' '; put_num(out, m.z[v]); out += '\n';
  }
  if (has_vt)
    for (size_t v = 0; v < nv; ++v) {
      out += "vt ";
      put_num(out, opt.uv ? (*opt.uv)[2 * v] : pu->values[v]);
      out += ' ';
      put_num(out, opt.uv ? (*opt.uv)[2 * v + 1] : pv->values[v]);
      out += '\n';
    }
  if (has_vn)
    for (size_t v = 0; v < nv; ++v) {
      out += "vn "; put_num(out, pnx->values[v]); out += ' '; put_num(out, pny->values[v]); out += ' ';
      put_num(out, pnz->values[v]); out += '\n';
    }
  const int64_t nf = m.num_faces();
  for (int64_t f = 0; f < nf; ++f) {
    out += 'f';
    for (int32_t j = m.face_offsets[f]; j < m.face_offsets[f + 1]; ++j) {
      const int64_t idx = int64_t(m.face_vertices[j]) + 1;  // OBJ is 1-based; vt i and vn i belong to vertex i
      out += ' ';
      put_num(out, idx);
      if (has_vt || has_vn) out += '/';
      if (has_vt) put_num(out, idx);
      if (has_vn) { out += '/'; put_num(out, idx); }
    }
    out += '\n';
  }
  append_obj_properties(out, rest, nv);
  return out;
}

// OFF has no named properties: one vertex property (opt.off_colour, else the
// first) is written as COFF
// colours (viridis over its finite range, grey for NaN/inf), so a viewer shows
// the result; the exact values need PLY or OBJ.
std::string off(const Mesh& m, const WriteOptions& opt) {
  const size_t nv = m.x.size();
  const int64_t nf = m.num_faces();
  const VertexProperty* shown = opt.vertex_properties.empty() ? nullptr : &opt.vertex_properties.front();
  for (const VertexProperty& p : opt.vertex_properties)
    if (p.name == opt.off_colour) shown = &p;
  std::string out = std::string(shown ? "COFF\n# colour: " + shown->name + "\n" : "OFF\n") + std::to_string(nv) +
                    " " + std::to_string(nf) + " 0\n";
  double lo = 0, hi = 0;
  if (shown) {
    bool any = false;
    for (double v : shown->values)
      if (std::isfinite(v)) { lo = any ? std::min(lo, v) : v; hi = any ? std::max(hi, v) : v; any = true; }
  }
  for (size_t v = 0; v < nv; ++v) {
    put_num(out, m.x[v]); out += ' '; put_num(out, m.y[v]); out += ' '; put_num(out, m.z[v]);
    if (shown) {
      const std::array<uint8_t, 3> c = scalar_colour(shown->values[v], lo, hi);
      for (uint8_t ch : c) { out += ' '; put_num(out, int64_t(ch)); }
      out += " 255";
    }
    out += '\n';
  }
  for (int64_t f = 0; f < nf; ++f) {
    put_num(out, int64_t(m.face_offsets[f + 1] - m.face_offsets[f]));
    for (int32_t j = m.face_offsets[f]; j < m.face_offsets[f + 1]; ++j) { out += ' '; put_num(out, int64_t(m.face_vertices[j])); }
    out += '\n';
  }
  return out;
}

}  // namespace

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& opt) {
  const std::string ext = lower_extension(path);
  if (ext != "ply" && ext != "obj" && ext != "off")
    usage(path, "unknown mesh file extension '" + ext + "' (expected .obj, .off or .ply)");
  validate(path, mesh, opt);
  if (ext == "off" && opt.uv) usage(path, "OFF has no texture coordinates: write .obj or .ply");
  const std::string bytes = ext == "ply" ? ply(mesh, opt) : ext == "obj" ? obj(mesh, opt) : off(mesh, opt);
  io::write_file_atomically(path, bytes);
}

}  // namespace locus
