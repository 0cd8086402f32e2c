// Factor cache files (io/factor_cache.hpp).
//
// Layout: "LOCUSFC\0", u32 format, u32 reserved, u64 flatbuffer size, the
// FactorCache flatbuffer (io/factor_cache.fbs), then raw little-endian arrays,
// each 8-byte aligned, described by the flatbuffer's sections. Loading checks,
// in this order and before allocating anything large: magic, format version,
// the flatbuffer (Verifier), every section inside the file with the expected
// element count, the checksums, then the structure (validate_symbolic) and
// the values (finite, positive diagonal).
#include "io/factor_cache.hpp"

#include <flatbuffers/flatbuffers.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <sys/stat.h>

#include "factor_cache_generated.h"
#include "locus/error.hpp"

namespace locus {

namespace {

constexpr char kMagic[8] = {'L', 'O', 'C', 'U', 'S', 'F', 'C', '\0'};
constexpr uint64_t kHeaderBytes = 24;

uint64_t checksum(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t h = 0xcbf29ce484222325ull;
  size_t i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = (h ^ w) * 0x100000001b3ull;
    h ^= h >> 31;
  }
  for (; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

uint64_t pad8(uint64_t x) { return (x + 7) & ~uint64_t(7); }

struct Array {
  const char* name;
  const void* data;
  uint64_t count;
  uint32_t elem;
};

template <typename V>
Array arr(const char* name, const V& v) {
  return {name, v.data(), static_cast<uint64_t>(v.size()), static_cast<uint32_t>(sizeof(typename V::value_type))};
}

std::vector<Array> arrays_of(const NumericFactor& f) {
  const SymbolicFactor& S = *f.symbolic;
  return {arr("perm", S.perm),           arr("iperm", S.iperm),
          arr("parent", S.parent),       arr("col_count", S.col_count),
          arr("super_first_col", S.super_first_col), arr("col_to_super", S.col_to_super),
          arr("super_parent", S.super_parent),       arr("super_row_ptr", S.super_row_ptr),
          arr("super_rows", S.super_rows),           arr("super_value_ptr", S.super_value_ptr),
          arr("a_super_ptr", S.a_super_ptr),         arr("a_src", S.a_src),
          arr("a_dst", S.a_dst),                     arr("values", f.values)};
}

std::vector<uint8_t> build_meta(const NumericFactor& f, const FactorCacheInfo& info, const std::vector<Array>& arrays,
                                const std::vector<uint64_t>& offsets, const std::vector<uint64_t>& sums) {
  const SymbolicFactor& S = *f.symbolic;
  flatbuffers::FlatBufferBuilder b;
  b.ForceDefaults(true);  // fixed size whatever the values: offsets are filled in a second pass
  std::vector<flatbuffers::Offset<fbs::Section>> secs;
  for (size_t k = 0; k < arrays.size(); ++k)
    secs.push_back(fbs::CreateSection(b, b.CreateString(arrays[k].name), offsets[k], arrays[k].count, arrays[k].elem, sums[k]));
  auto sv = b.CreateVector(secs);
  auto ver = b.CreateString("locus 0.1");
  auto kind = b.CreateString(info.operator_kind);
  fbs::FactorCacheBuilder fb(b);
  fb.add_format_version(kFactorCacheFormat);
  fb.add_locus_version(ver);
  fb.add_mesh_hash(info.mesh_hash);
  fb.add_operator_kind(kind);
  fb.add_t(info.t);
  fb.add_n(S.n);
  fb.add_ns(S.ns);
  fb.add_nnz_exact(S.nnz_exact);
  fb.add_nnz_l(S.nnz_L);
  fb.add_etree_height(S.etree_height);
  fb.add_super_etree_height(S.super_etree_height);
  fb.add_a_pattern_hash(S.a_pattern_hash);
  fb.add_a_nnz(S.a_nnz);
  fb.add_max_update_entries(S.max_update_entries);
  fb.add_max_super_rows(S.max_super_rows);
  fb.add_sections(sv);
  b.Finish(fb.Finish());
  return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

[[noreturn]] void bad_file(const std::string& path, const std::string& why) {
  fail(ErrorCode::BadInput, path + ": " + why);
}

}  // namespace

uint64_t mesh_content_hash(const Mesh& m) {
  uint64_t h = checksum(m.x.data(), m.x.size() * sizeof(double));
  h ^= checksum(m.y.data(), m.y.size() * sizeof(double)) * 3;
  h ^= checksum(m.z.data(), m.z.size() * sizeof(double)) * 5;
  h ^= checksum(m.face_offsets.data(), m.face_offsets.size() * sizeof(int32_t)) * 7;
  h ^= checksum(m.face_vertices.data(), m.face_vertices.size() * sizeof(int32_t)) * 11;
  return h ? h : 1;
}

void save_factor(const std::string& path, const NumericFactor& f, const FactorCacheInfo& info) {
  if (!f.symbolic) fail(ErrorCode::BadUsage, "save_factor: empty factor");
  const std::vector<Array> arrays = arrays_of(f);
  std::vector<uint64_t> sums(arrays.size()), offsets(arrays.size(), 0);
  for (size_t k = 0; k < arrays.size(); ++k) sums[k] = checksum(arrays[k].data, arrays[k].count * arrays[k].elem);
  const uint64_t meta_size = build_meta(f, info, arrays, offsets, sums).size();
  uint64_t pos = pad8(kHeaderBytes + meta_size);
  for (size_t k = 0; k < arrays.size(); ++k) {
    offsets[k] = pos;
    pos = pad8(pos + arrays[k].count * arrays[k].elem);
  }
  const std::vector<uint8_t> meta = build_meta(f, info, arrays, offsets, sums);
  if (meta.size() != meta_size) fail(ErrorCode::Internal, "factor cache metadata changed size between passes");
  // Write to a temporary name and rename: a crash never leaves a half-written cache under the real name.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(ErrorCode::BadInput, path + ": cannot open for writing");
    const uint32_t fmt = kFactorCacheFormat, reserved = 0;
    out.write(kMagic, 8);
    out.write(reinterpret_cast<const char*>(&fmt), 4);
    out.write(reinterpret_cast<const char*>(&reserved), 4);
    out.write(reinterpret_cast<const char*>(&meta_size), 8);
    out.write(reinterpret_cast<const char*>(meta.data()), static_cast<std::streamsize>(meta.size()));
    static const char zeros[8] = {};
    uint64_t at = kHeaderBytes + meta_size;
    for (size_t k = 0; k < arrays.size(); ++k) {
      out.write(zeros, static_cast<std::streamsize>(offsets[k] - at));
      out.write(static_cast<const char*>(arrays[k].data), static_cast<std::streamsize>(arrays[k].count * arrays[k].elem));
      at = offsets[k] + arrays[k].count * arrays[k].elem;
    }
    if (!out) fail(ErrorCode::BadInput, path + ": write failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(ErrorCode::BadInput, path + ": cannot rename " + tmp);
}

NumericFactor load_factor(const std::string& path, FactorCacheInfo& info, uint64_t expected_mesh_hash) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) bad_file(path, "no such file");
  if (!S_ISREG(st.st_mode)) bad_file(path, "not a regular file");
  const uint64_t file_size = static_cast<uint64_t>(st.st_size);
  std::ifstream in(path, std::ios::binary);
  if (!in) bad_file(path, "cannot open");
  if (file_size < kHeaderBytes) bad_file(path, "truncated (no header)");
  char magic[8];
  uint32_t fmt = 0, reserved = 0;
  uint64_t meta_size = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&fmt), 4);
  in.read(reinterpret_cast<char*>(&reserved), 4);
  in.read(reinterpret_cast<char*>(&meta_size), 8);
  if (std::memcmp(magic, kMagic, 8) != 0) bad_file(path, "not a locus factor cache");
  if (fmt != kFactorCacheFormat)
    bad_file(path, "factor cache format " + std::to_string(fmt) + ", this locus reads format " + std::to_string(kFactorCacheFormat));
  if (meta_size > file_size - kHeaderBytes || meta_size > (64u << 20)) bad_file(path, "truncated or corrupted metadata");
  std::vector<uint8_t> meta(meta_size);
  in.read(reinterpret_cast<char*>(meta.data()), static_cast<std::streamsize>(meta_size));
  if (!in) bad_file(path, "truncated metadata");
  flatbuffers::Verifier verifier(meta.data(), meta.size());
  if (!fbs::VerifyFactorCacheBuffer(verifier)) bad_file(path, "corrupted metadata");
  const fbs::FactorCache* fc = fbs::GetFactorCache(meta.data());
  if (fc->format_version() != kFactorCacheFormat) bad_file(path, "format version mismatch in metadata");
  info.mesh_hash = fc->mesh_hash();
  info.operator_kind = fc->operator_kind() ? fc->operator_kind()->str() : "";
  info.t = fc->t();
  if (expected_mesh_hash != 0 && info.mesh_hash != expected_mesh_hash)
    bad_file(path, "factor was made for another mesh (content hash differs)");

  auto S = std::make_shared<SymbolicFactor>();
  NumericFactor f;
  S->n = fc->n();
  S->ns = fc->ns();
  S->nnz_exact = fc->nnz_exact();
  S->nnz_L = fc->nnz_l();
  S->etree_height = fc->etree_height();
  S->super_etree_height = fc->super_etree_height();
  S->a_pattern_hash = fc->a_pattern_hash();
  S->a_nnz = fc->a_nnz();
  if (S->n < 0 || S->ns < 0 || S->a_nnz < 0) bad_file(path, "negative sizes");
  std::map<std::string, const fbs::Section*> secs;
  if (!fc->sections()) bad_file(path, "no sections");
  for (const fbs::Section* s : *fc->sections())
    if (s && s->name()) secs[s->name()->str()] = s;
  // Reads one section into v after checking it lies inside the file and has the element size of v.
  auto load = [&](const char* name, auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    auto it = secs.find(name);
    if (it == secs.end()) bad_file(path, std::string("missing section ") + name);
    const fbs::Section* s = it->second;
    if (s->elem_size() != sizeof(T)) bad_file(path, std::string("section ") + name + " has the wrong element size");
    if (s->offset() > file_size || s->count() > (file_size - s->offset()) / sizeof(T))
      bad_file(path, std::string("truncated: section ") + name + " extends past the end of the file");
    v.resize(s->count());
    in.seekg(static_cast<std::streamoff>(s->offset()));
    in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(s->count() * sizeof(T)));
    if (!in) bad_file(path, std::string("cannot read section ") + name);
    if (checksum(v.data(), v.size() * sizeof(T)) != s->checksum())
      bad_file(path, std::string("corrupted: checksum mismatch in section ") + name);
  };
  load("perm", S->perm);
  load("iperm", S->iperm);
  load("parent", S->parent);
  load("col_count", S->col_count);
  load("super_first_col", S->super_first_col);
  load("col_to_super", S->col_to_super);
  load("super_parent", S->super_parent);
  load("super_row_ptr", S->super_row_ptr);
  load("super_rows", S->super_rows);
  load("super_value_ptr", S->super_value_ptr);
  load("a_super_ptr", S->a_super_ptr);
  load("a_src", S->a_src);
  load("a_dst", S->a_dst);
  load("values", f.values);
  validate_symbolic(*S, static_cast<int64_t>(f.values.size()));
  // Derived data is recomputed, not trusted.
  compute_update_lists(*S);
  S->max_super_rows = 0;
  for (int32_t s = 0; s < S->ns; ++s) S->max_super_rows = std::max(S->max_super_rows, S->nrows(s));
  for (int32_t s = 0; s < S->ns; ++s) {
    const double* L = f.values.data() + S->super_value_ptr[s];
    for (int32_t j = 0; j < S->ncols(s); ++j) {
      const double d = L[static_cast<int64_t>(j) * S->nrows(s) + j];
      if (!(d > 0) || !std::isfinite(d)) bad_file(path, "corrupted: non-positive diagonal in the factor");
      for (int32_t i = j; i < S->nrows(s); ++i)
        if (!std::isfinite(L[static_cast<int64_t>(j) * S->nrows(s) + i])) bad_file(path, "corrupted: non-finite factor entry");
    }
  }
  f.symbolic = std::move(S);
  return f;
}

}  // namespace locus
