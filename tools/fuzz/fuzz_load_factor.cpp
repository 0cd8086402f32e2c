// libFuzzer target for the factor-cache loader (io/src/factor_cache.cpp,
// load_factors, which load_factor wraps). The input is the file. The only acceptable outcomes are a
// factor or a locus::Error; any other exception, crash, sanitizer report, hang
// (-timeout) or memory blow-up (-rss_limit_mb) is a finding. A loaded factor is
// then (its last factor) used for a full solve, an 8-lane solve and a subset solve, so that a
// structure the validator let through but a solve cannot index shows up
// under ASan.
//
// Every section carries a checksum, so almost every mutation of the raw file
// would stop at the checksum test. To reach the structural validation behind
// it, the target repairs the checksums of inputs whose metadata parses (the
// same hash as io/src/factor_cache.cpp, recomputed over the mutated bytes) for
// three inputs in four (size % 4 != 3); the others are loaded as they are.
//
// Seeds: LOCUS_FUZZ_WRITE_SEEDS=DIR fuzz_load_factor writes small valid caches
// (save_factor of grid heat operators, one save_factors file with two factors)
// and truncations of them into DIR and
// exits; tests/fuzz_corpus/load_factor/ holds their output.
#include <flatbuffers/flatbuffers.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "factor_cache_generated.h"
#include "locus/io/factor_cache.hpp"
#include "locus/kernels/mesh/mesh_generators.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/error.hpp"

namespace {

constexpr size_t kHeaderBytes = 24;

// The section checksum of io/src/factor_cache.cpp (FNV-1a over 8-byte words, then the tail).
uint64_t checksum(const uint8_t* p, size_t bytes) {
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

// Address of a scalar field of a verified flatbuffer table (its vtable lookup;
// the generated accessors inherit flatbuffers::Table privately), or nullptr.
const uint8_t* field_address(const void* table, flatbuffers::voffset_t field) {
  const auto* t = static_cast<const uint8_t*>(table);
  const uint8_t* vt = t - flatbuffers::ReadScalar<flatbuffers::soffset_t>(t);
  if (field >= flatbuffers::ReadScalar<flatbuffers::voffset_t>(vt)) return nullptr;
  const auto off = flatbuffers::ReadScalar<flatbuffers::voffset_t>(vt + field);
  return off ? t + off : nullptr;
}

// Rewrites the checksum field of every section that lies inside the file.
void repair_checksums(std::vector<uint8_t>& file) {
  if (file.size() < kHeaderBytes) return;
  uint64_t meta_size = 0;
  std::memcpy(&meta_size, file.data() + 16, 8);
  if (meta_size > file.size() - kHeaderBytes) return;
  uint8_t* meta = file.data() + kHeaderBytes;
  // The flatbuffer may sit at an unaligned address in the vector; verify a copy.
  std::vector<uint8_t> copy(meta, meta + meta_size);
  flatbuffers::Verifier verifier(copy.data(), copy.size());
  if (!locus::fbs::VerifyFactorCacheBuffer(verifier)) return;
  const locus::fbs::FactorCache* fc = locus::fbs::GetFactorCache(copy.data());
  if (!fc->sections()) return;
  for (const locus::fbs::Section* s : *fc->sections()) {
    if (!s) continue;
    const uint8_t* field = field_address(s, locus::fbs::Section::VT_CHECKSUM);
    if (!field) continue;
    const uint64_t off = s->offset(), elem = s->elem_size();
    if (elem == 0 || off > file.size() || s->count() > (file.size() - off) / elem) continue;
    const uint64_t sum = checksum(file.data() + off, s->count() * elem);
    std::memcpy(meta + (field - copy.data()), &sum, 8);
  }
}

std::string scratch_path() {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir && *dir ? dir : "/tmp") + "/locus_fuzz_load_factor_" + std::to_string(::getpid()) + ".bin";
}

void write_file(const std::string& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

void write_seeds(const std::string& dir) {
  int k = 0;
  for (int32_t n : {1, 2, 3, 5}) {
    const locus::Mesh m = locus::make_grid(n, 0.3, 7);
    const locus::CscMatrix A = locus::heat_operator(m, 0.01);
    const locus::NumericFactor F = locus::factorize(locus::analyze(A, locus::order_matrix(A)), A);
    const std::string path = dir + "/grid" + std::to_string(n) + ".locusfc";
    locus::save_factor(path, F, {static_cast<uint64_t>(1000 + n), "heat", 0.01});
    if (n == 3) {  // several factors on one symbolic factor (save_factors)
      const locus::NumericFactor G = locus::factorize(F.symbolic, locus::heat_operator(m, 0.1));
      const locus::FactorEntry entries[2] = {{"heat", 0.01, &F}, {"heat", 0.1, &G}};
      locus::save_factors(dir + "/grid3_two_factors.locusfc", 1003, entries);
    }
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    // Truncations: inside the header, inside the metadata, inside the arrays.
    for (size_t cut : {size_t(20), size_t(100), bytes.size() / 2, bytes.size() - 8}) {
      if (cut >= bytes.size() || (k++ % 2 == 1 && n > 2)) continue;
      std::ofstream out(dir + "/grid" + std::to_string(n) + "_cut" + std::to_string(cut) + ".locusfc", std::ios::binary);
      out.write(bytes.data(), static_cast<std::streamsize>(cut));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("LOCUS_FUZZ_WRITE_SEEDS")) {
    write_seeds(dir);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = scratch_path();
  std::vector<uint8_t> file(data, data + size);
  if (size % 4 != 3) repair_checksums(file);
  write_file(path, file.data(), file.size());
  try {
    const locus::LoadedFactors loaded = locus::load_factors(path);
    if (loaded.factors.empty()) std::abort();  // a successful load holds at least one factor
    const locus::NumericFactor& F = loaded.factors.back();
    const int32_t n = F.n();
    std::vector<double> b(static_cast<size_t>(n), 1.0);
    locus::solve(F, b);
    std::vector<double> b8(static_cast<size_t>(n) * locus::kLanes, 0.5);
    locus::solve8(F, b8);
    if (n > 0) {
      const int32_t first = 0, last = n - 1;
      const locus::SolvePlan plan = locus::plan_subset_solve(*F.symbolic, {&first, 1}, {&last, 1});
      locus::SolveWorkspace ws;
      double rhs = 1.0, out = 0.0;
      locus::solve_planned(F, plan, {&rhs, 1}, {&out, 1}, ws);
    }
  } catch (const locus::Error&) {
  }
  return 0;
}
