// Shared tokenizing, number parsing and error formatting for the mesh readers
// (io/src/read_obj.cpp, io/src/read_off.cpp, io/src/read_ply.cpp). Internal to io/.
//
// Not from the thesis: this is file-format plumbing. The readers take the whole
// file as one buffer and walk it with pointers; numbers go through
// std::from_chars (no locale, no iostream, no allocation per token). Every
// routine here is bounded by the buffer it is given, so hostile input can make a
// reader fail but never read past the end.
#pragma once
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "locus/error.hpp"

namespace locus::io {

// A line longer than this is not a mesh file line; refusing it keeps a hostile
// file from making us look for a newline in gigabytes of garbage per "line".
// 1 MiB still holds a polygon with more than 100k corners.
inline constexpr size_t kMaxLineBytes = size_t(1) << 20;

// The largest vertex / face / corner count a Mesh can index (int32 ids).
inline constexpr int64_t kMaxCount = std::numeric_limits<int32_t>::max();

// A short, printable rendering of a token for error messages: at most 32
// characters, non-printable bytes shown as \xNN, so garbage input cannot make a
// message huge or unreadable.
inline std::string quote(std::string_view tok) {
  static const char* hex = "0123456789abcdef";
  std::string s = "'";
  size_t n = 0;
  for (char ch : tok) {
    if (n++ == 32) { s += "..."; break; }
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f) {
      s += ch;
    } else {
      s += "\\x";
      s += hex[c >> 4];
      s += hex[c & 15];
    }
  }
  s += "'";
  return s;
}

[[noreturn]] inline void fail_line(const std::string& name, int64_t line, const std::string& msg) {
  fail(ErrorCode::BadInput, name + ":" + std::to_string(line) + ": " + msg);
}

[[noreturn]] inline void fail_offset(const std::string& name, uint64_t offset, const std::string& msg) {
  fail(ErrorCode::BadInput, name + ": byte " + std::to_string(offset) + ": " + msg);
}

// Parses all of `tok` as a double. Accepts a leading '+', which from_chars does
// not. Returns false for anything else than a complete number (including
// overflow such as "1e999"); "nan"/"inf" parse and must be rejected by the
// caller (with a message that says which vertex).
inline bool parse_double(std::string_view tok, double& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out, std::chars_format::general);
  return r.ec == std::errc() && r.ptr == e;
}

// Parses all of `tok` as a signed 64-bit integer (leading '+' allowed).
inline bool parse_int(std::string_view tok, int64_t& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+' && e - b > 1 && b[1] != '-') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e;
}

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Whitespace-separated fields of one line.
class Fields {
 public:
  explicit Fields(std::string_view line) : p_(line.data()), e_(line.data() + line.size()) {}
  // The next field, or an empty view when the line is used up.
  std::string_view next() {
    while (p_ != e_ && is_blank(*p_)) ++p_;
    const char* b = p_;
    while (p_ != e_ && !is_blank(*p_)) ++p_;
    return {b, static_cast<size_t>(p_ - b)};
  }
  bool done() {
    while (p_ != e_ && is_blank(*p_)) ++p_;
    return p_ == e_;
  }
  std::string_view rest() const { return {p_, static_cast<size_t>(e_ - p_)}; }

 private:
  const char* p_;
  const char* e_;
};

// Walks a text buffer line by line, counting lines (1-based) for messages.
class LineReader {
 public:
  LineReader(std::string_view text, const std::string& name)
      : p_(text.data()), end_(text.data() + text.size()), name_(&name) {
    // A UTF-8 byte-order mark is not content.
    if (end_ - p_ >= 3 && std::memcmp(p_, "\xEF\xBB\xBF", 3) == 0) p_ += 3;
  }

  // Sets `line` to the next line without its '\n'; false at the end of the text.
  bool next(std::string_view& line) {
    if (p_ == end_) return false;
    ++line_;
    const size_t avail = static_cast<size_t>(end_ - p_);
    const size_t scan = avail < kMaxLineBytes + 1 ? avail : kMaxLineBytes + 1;
    const char* nl = static_cast<const char*>(std::memchr(p_, '\n', scan));
    const char* e = nl ? nl : p_ + scan;
    if (static_cast<size_t>(e - p_) > kMaxLineBytes)
      fail_line(*name_, line_, "line is longer than " + std::to_string(kMaxLineBytes) + " bytes (not a mesh file?)");
    line = {p_, static_cast<size_t>(e - p_)};
    p_ = nl ? nl + 1 : end_;
    return true;
  }

  // Like next(), but drops a '#' comment and skips lines that are then blank.
  bool next_content(std::string_view& line) {
    while (next(line)) {
      line = strip_comment(line);
      if (!Fields(line).done()) return true;
    }
    return false;
  }

  static std::string_view strip_comment(std::string_view line) {
    const size_t h = line.find('#');
    return h == std::string_view::npos ? line : line.substr(0, h);
  }

  int64_t line_number() const { return line_; }
  // Bytes not yet consumed (used to bound header counts before allocating).
  uint64_t remaining() const { return static_cast<uint64_t>(end_ - p_); }
  const char* position() const { return p_; }
  [[noreturn]] void fail(const std::string& msg) const { fail_line(*name_, line_, msg); }

 private:
  const char* p_;
  const char* end_;
  const std::string* name_;  // a pointer so that a reader can be copied to look ahead
  int64_t line_ = 0;
};

// a*b saturated at UINT64_MAX, for "can the file possibly hold this many
// records" checks that must not wrap around on hostile counts.
inline uint64_t sat_mul(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}
inline uint64_t sat_add(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_add_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

// A coordinate rendered for messages ("nan", "inf", "-inf" or the number).
inline std::string coord_text(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Inf" : "-Inf";
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace locus::io
