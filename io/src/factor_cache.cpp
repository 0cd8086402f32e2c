// Factor cache files (io/include/locus/io/factor_cache.hpp).
//
// Layout: "LOCUSFC\0", u32 format, u32 reserved, u64 flatbuffer size, the
// FactorCache flatbuffer (io/schema/factor_cache.fbs), then raw little-endian arrays,
// each 8-byte aligned, described by the flatbuffer's sections. Loading checks,
// in this order and before allocating anything large: magic, format version,
// the flatbuffer (Verifier), every section inside the file with the expected
// element count, the checksums, then the structure (validate_symbolic) and
// the values (finite, positive diagonal). Sections are hashed in 4 MiB blocks
// (fbs Section.block_bytes) so that reading and checking run in parallel on the
// caller's threads; files with block_bytes = 0 hold one hash per section.
#include "locus/io/factor_cache.hpp"

#include <flatbuffers/flatbuffers.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "factor_cache_generated.h"
#include "locus/io/atomic_file_write.hpp"
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

// Sections are hashed in blocks of this size: each block is read and hashed by
// one task while it is still in cache, and the blocks of a large section are
// spread over the threads. The section checksum is the hash of the block hashes.
constexpr uint64_t kBlockBytes = uint64_t(4) << 20;

uint64_t blocked_checksum(const void* data, uint64_t bytes, uint64_t block) {
  const uint64_t nb = bytes == 0 ? 0 : (bytes + block - 1) / block;
  std::vector<uint64_t> h(nb);
  const auto* p = static_cast<const char*>(data);
  tbb::parallel_for(uint64_t(0), nb, [&](uint64_t b) {
    h[b] = checksum(p + b * block, static_cast<size_t>(std::min(block, bytes - b * block)));
  });
  return checksum(h.data(), h.size() * sizeof(uint64_t));
}

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

// Calls f(name, array) for every array of the symbolic factor the file keeps,
// in file order: the one list the writer and the reader share.
template <class Symbolic, class F>
void for_each_symbolic_array(Symbolic& S, F&& f) {
  f("perm", S.perm), f("iperm", S.iperm), f("parent", S.parent), f("col_count", S.col_count);
  f("super_first_col", S.super_first_col), f("col_to_super", S.col_to_super), f("super_parent", S.super_parent);
  f("super_row_ptr", S.super_row_ptr), f("super_rows", S.super_rows), f("super_value_ptr", S.super_value_ptr);
  f("a_super_ptr", S.a_super_ptr), f("a_src", S.a_src), f("a_dst", S.a_dst);
}

// The symbolic arrays, then one values section per factor.
std::vector<Array> arrays_of(const SymbolicFactor& S, std::span<const FactorEntry> entries,
                             std::vector<std::string>& value_names) {
  std::vector<Array> a;
  for_each_symbolic_array(S, [&](const char* name, const auto& v) { a.push_back(arr(name, v)); });
  value_names.clear();
  for (size_t k = 0; k < entries.size(); ++k) value_names.push_back(k == 0 ? "values" : "values" + std::to_string(k));
  for (size_t k = 0; k < entries.size(); ++k) a.push_back(arr(value_names[k].c_str(), entries[k].factor->values));
  return a;
}

std::vector<uint8_t> build_meta(const SymbolicFactor& S, uint64_t mesh_hash, std::span<const FactorEntry> entries,
                                const std::vector<std::string>& value_names, const std::vector<Array>& arrays,
                                const std::vector<uint64_t>& offsets, const std::vector<uint64_t>& sums) {
  flatbuffers::FlatBufferBuilder b;
  b.ForceDefaults(true);  // fixed size whatever the values: offsets are filled in a second pass
  std::vector<flatbuffers::Offset<fbs::Section>> secs;
  for (size_t k = 0; k < arrays.size(); ++k)
    secs.push_back(fbs::CreateSection(b, b.CreateString(arrays[k].name), offsets[k], arrays[k].count, arrays[k].elem,
                                      sums[k], kBlockBytes));
  auto sv = b.CreateVector(secs);
  std::vector<flatbuffers::Offset<fbs::Factor>> facs;
  for (size_t k = 0; k < entries.size(); ++k)
    facs.push_back(fbs::CreateFactor(b, b.CreateString(entries[k].operator_kind), entries[k].t,
                                     b.CreateString(value_names[k])));
  auto fv = b.CreateVector(facs);
  auto ver = b.CreateString("locus 0.1");
  auto kind = b.CreateString(entries[0].operator_kind);
  fbs::FactorCacheBuilder fb(b);
  fb.add_format_version(kFactorCacheFormat);
  fb.add_locus_version(ver);
  fb.add_mesh_hash(mesh_hash);
  fb.add_operator_kind(kind);
  fb.add_t(entries[0].t);
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
  fb.add_factors(fv);
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

void save_factors(const std::string& path, uint64_t mesh_hash, std::span<const FactorEntry> entries) {
  if (entries.empty()) fail(ErrorCode::BadUsage, "save_factors: no factor to save");
  for (const FactorEntry& e : entries) {
    if (!e.factor || !e.factor->symbolic) fail(ErrorCode::BadUsage, "save_factors: empty factor");
    if (e.factor->borrows())
      fail(ErrorCode::BadUsage, "save_factors: the factor borrows blocks from another factor (a factor-once result); "
                                "only self-contained factors are cached");
    if (e.factor->symbolic != entries[0].factor->symbolic)
      fail(ErrorCode::BadUsage, "save_factors: the factors of one file must share one symbolic factor");
  }
  const SymbolicFactor& S = *entries[0].factor->symbolic;
  std::vector<std::string> value_names;
  const std::vector<Array> arrays = arrays_of(S, entries, value_names);
  std::vector<uint64_t> sums(arrays.size()), offsets(arrays.size(), 0);
  for (size_t k = 0; k < arrays.size(); ++k)
    sums[k] = blocked_checksum(arrays[k].data, arrays[k].count * arrays[k].elem, kBlockBytes);
  const uint64_t meta_size = build_meta(S, mesh_hash, entries, value_names, arrays, offsets, sums).size();
  uint64_t pos = pad8(kHeaderBytes + meta_size);
  for (size_t k = 0; k < arrays.size(); ++k) {
    offsets[k] = pos;
    pos = pad8(pos + arrays[k].count * arrays[k].elem);
  }
  const std::vector<uint8_t> meta = build_meta(S, mesh_hash, entries, value_names, arrays, offsets, sums);
  if (meta.size() != meta_size) fail(ErrorCode::Internal, "factor cache metadata changed size between passes");
  io::write_file_atomically(path, [&](std::ostream& out) {
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
  });
}

void save_factor(const std::string& path, const NumericFactor& f, const FactorCacheInfo& info) {
  const FactorEntry e{info.operator_kind, info.t, &f};
  save_factors(path, info.mesh_hash, std::span<const FactorEntry>(&e, 1));
}

namespace {

// Closes the descriptor on every exit path.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// Reads exactly `bytes` at `offset` with large pread calls (no stream buffer copy).
bool read_at(int fd, void* dst, uint64_t bytes, uint64_t offset) {
  auto* p = static_cast<char*>(dst);
  while (bytes > 0) {
    const size_t chunk = static_cast<size_t>(std::min<uint64_t>(bytes, uint64_t(1) << 30));
    const ssize_t got = ::pread(fd, p, chunk, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return false;
    p += got;
    offset += static_cast<uint64_t>(got);
    bytes -= static_cast<uint64_t>(got);
  }
  return true;
}

// A loaded factor's values: a positive diagonal and finite entries. 0 = fine,
// 1 = a non-positive diagonal, 2 = a non-finite entry; the first supernode at
// fault decides, so the message does not depend on the threads.
void check_factor_values(const std::string& path, const SymbolicFactor& S, std::span<const double> values) {
  std::vector<uint8_t> fault(static_cast<size_t>(S.ns), 0);
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, S.ns, 64), [&](const tbb::blocked_range<int32_t>& r) {
    for (int32_t s = r.begin(); s < r.end(); ++s) {
      const double* L = values.data() + S.super_value_ptr[s];
      const int32_t nr = S.nrows(s);
      for (int32_t j = 0; j < S.ncols(s) && !fault[s]; ++j) {
        const double* col = L + static_cast<int64_t>(j) * nr;
        if (!(col[j] > 0) || !std::isfinite(col[j])) fault[s] = 1;
        // Finite test without a branch per entry: x - x is 0 for finite x, NaN otherwise.
        double probe = 0;
        for (int32_t i = j; i < nr; ++i) probe += col[i] - col[i];
        if (probe != 0 && !fault[s]) fault[s] = 2;
      }
    }
  });
  for (uint8_t e : fault) {
    if (e == 1) bad_file(path, "corrupted: non-positive diagonal in the factor");
    if (e == 2) bad_file(path, "corrupted: non-finite factor entry");
  }
}

// The header (magic, format) and the flatbuffers metadata after it, verified.
std::vector<uint8_t> read_metadata(const std::string& path, int fd, uint64_t file_size) {
  char header[kHeaderBytes];
  if (!read_at(fd, header, kHeaderBytes, 0)) bad_file(path, "cannot read the header");
  uint32_t fmt = 0;
  uint64_t meta_size = 0;
  std::memcpy(&fmt, header + 8, 4);
  std::memcpy(&meta_size, header + 16, 8);
  if (std::memcmp(header, kMagic, 8) != 0) bad_file(path, "not a locus factor cache");
  if (fmt != kFactorCacheFormat)
    bad_file(path, "factor cache format " + std::to_string(fmt) + ", this locus reads format " + std::to_string(kFactorCacheFormat));
  if (meta_size > file_size - kHeaderBytes || meta_size > (64u << 20)) bad_file(path, "truncated or corrupted metadata");
  std::vector<uint8_t> meta(meta_size);
  if (!read_at(fd, meta.data(), meta_size, kHeaderBytes)) bad_file(path, "truncated metadata");
  flatbuffers::Verifier verifier(meta.data(), meta.size());
  if (!fbs::VerifyFactorCacheBuffer(verifier)) bad_file(path, "corrupted metadata");
  return meta;
}

// The numeric factors a file holds: the `factors` list, or (older files) one "values" section.
struct FactorLabel {
  std::string kind, section;
  double t;
};

std::vector<FactorLabel> factor_labels(const std::string& path, const fbs::FactorCache* fc) {
  std::vector<FactorLabel> labels;
  if (fc->factors()) {
    for (const fbs::Factor* f : *fc->factors()) {
      if (!f || !f->section()) bad_file(path, "corrupted: factor without a values section");
      labels.push_back({f->operator_kind() ? f->operator_kind()->str() : "", f->section()->str(), f->t()});
    }
  } else {
    labels.push_back({fc->operator_kind() ? fc->operator_kind()->str() : "", "values", fc->t()});
  }
  if (labels.empty()) bad_file(path, "holds no factor");
  return labels;
}

}  // namespace

LoadedFactors load_factors(const std::string& path, uint64_t expected_mesh_hash) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) bad_file(path, "no such file");
  if (!S_ISREG(st.st_mode)) bad_file(path, "not a regular file");
  const uint64_t file_size = static_cast<uint64_t>(st.st_size);
  Fd file;
  file.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (file.fd < 0) bad_file(path, "cannot open");
  if (file_size < kHeaderBytes) bad_file(path, "truncated (no header)");
  const std::vector<uint8_t> meta = read_metadata(path, file.fd, file_size);
  const fbs::FactorCache* fc = fbs::GetFactorCache(meta.data());
  if (fc->format_version() != kFactorCacheFormat) bad_file(path, "format version mismatch in metadata");
  LoadedFactors out;
  out.mesh_hash = fc->mesh_hash();
  if (expected_mesh_hash != 0 && out.mesh_hash != expected_mesh_hash)
    bad_file(path, "factor was made for another mesh (content hash differs)");

  auto S = std::make_shared<SymbolicFactor>();
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
  auto load = [&](const std::string& name, auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    auto it = secs.find(name);
    if (it == secs.end()) bad_file(path, "missing section " + name);
    const fbs::Section* s = it->second;
    if (s->elem_size() != sizeof(T)) bad_file(path, "section " + name + " has the wrong element size");
    if (s->offset() > file_size || s->count() > (file_size - s->offset()) / sizeof(T))
      bad_file(path, "truncated: section " + name + " extends past the end of the file");
    // (Transparent huge pages for these buffers were tried: with defrag=madvise the
    // compaction stalls made a 200 MB load 30% slower than 4 KiB page faults.)
    v.resize(s->count());
    const uint64_t bytes = s->count() * sizeof(T);
    const uint64_t block = s->block_bytes();
    uint64_t sum = 0;
    if (block == 0) {  // one hash over the section
      if (!read_at(file.fd, v.data(), bytes, s->offset())) bad_file(path, "cannot read section " + name);
      sum = checksum(v.data(), bytes);
    } else {
      if (block % 8 != 0 || block < 4096 || block > (uint64_t(1) << 30))
        bad_file(path, "corrupted: section " + name + " has an invalid block size");
      // Each block is read and hashed by one task (while it is in cache); blocks run in parallel.
      const uint64_t nb = (bytes + block - 1) / block;
      std::vector<uint64_t> h(nb);
      std::atomic<bool> short_read{false};
      char* dst = reinterpret_cast<char*>(v.data());
      tbb::parallel_for(uint64_t(0), nb, [&](uint64_t b) {
        const uint64_t len = std::min(block, bytes - b * block);
        if (!read_at(file.fd, dst + b * block, len, s->offset() + b * block)) short_read = true;
        h[b] = checksum(dst + b * block, static_cast<size_t>(len));
      });
      if (short_read) bad_file(path, "cannot read section " + name);
      sum = checksum(h.data(), h.size() * sizeof(uint64_t));
    }
    if (sum != s->checksum()) bad_file(path, "corrupted: checksum mismatch in section " + name);
  };
  for_each_symbolic_array(*S, [&](const char* name, auto& v) { load(name, v); });
  const std::vector<FactorLabel> labels = factor_labels(path, fc);
  out.factors.resize(labels.size());
  for (size_t k = 0; k < labels.size(); ++k) {
    load(labels[k].section, out.factors[k].values);
    if (static_cast<int64_t>(out.factors[k].values.size()) != static_cast<int64_t>(out.factors[0].values.size()))
      bad_file(path, "corrupted: factors of different sizes");
    out.operator_kinds.push_back(labels[k].kind);
    out.t.push_back(labels[k].t);
  }
  validate_symbolic(*S, static_cast<int64_t>(out.factors[0].values.size()));
  // Derived data is recomputed, not trusted.
  compute_update_lists(*S);
  S->max_super_rows = 0;
  for (int32_t s = 0; s < S->ns; ++s) S->max_super_rows = std::max(S->max_super_rows, S->nrows(s));
  for (NumericFactor& f : out.factors) {
    check_factor_values(path, *S, f.values);
    f.symbolic = S;
  }
  return out;
}

NumericFactor load_factor(const std::string& path, FactorCacheInfo& info, uint64_t expected_mesh_hash) {
  LoadedFactors L = load_factors(path, expected_mesh_hash);
  info.mesh_hash = L.mesh_hash;
  info.operator_kind = L.operator_kinds[0];
  info.t = L.t[0];
  return std::move(L.factors[0]);
}

}  // namespace locus
