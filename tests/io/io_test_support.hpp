// Helpers shared by the io tests: run a read and capture the locus::Error it
// raises, a scratch directory for written files, and a tiny independent byte
// writer for building binary PLY fixtures (so the reader is not tested against
// locus's own writer).
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "locus/error.hpp"
#include "locus/mesh_io.hpp"

namespace locus_test {

struct Caught {
  bool thrown = false;
  locus::ErrorCode code = locus::ErrorCode::Internal;
  std::string message;
  bool has(std::string_view s) const { return message.find(s) != std::string::npos; }
};

template <class F>
Caught catch_error(F&& f) {
  try {
    f();
  } catch (const locus::Error& e) {
    return {true, e.code(), e.what()};
  }
  return {};
}

inline locus::Mesh parse(std::string_view text, const std::string& fmt, const locus::ReadOptions& opt = {}) {
  return locus::read_mesh_from_memory(text.data(), text.size(), fmt, "t." + fmt, opt);
}

inline Caught parse_error(std::string_view text, const std::string& fmt, const locus::ReadOptions& opt = {}) {
  return catch_error([&] { parse(text, fmt, opt); });
}

inline std::filesystem::path scratch_dir() {
  const auto d = std::filesystem::path(LOCUS_BINARY_DIR) / "io_test_scratch";
  std::filesystem::create_directories(d);
  return d;
}

inline std::string data_dir() { return std::string(LOCUS_TEST_DATA_DIR) + "/io"; }

// Appends v to s in the requested byte order.
template <class T>
void put(std::string& s, T v, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  const bool host_big = std::endian::native == std::endian::big;
  if (big_endian != host_big)
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  s.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace locus_test
