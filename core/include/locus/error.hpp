// locus::Error — the one exception type of the library.
//
// Every failure names what is wrong and where (file and line, face, vertex,
// column). The code mirrors the CLI's exit status so that tools can map an
// error to a status without parsing the message.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

enum class ErrorCode : int {
  BadUsage = 2,      // wrong arguments / options from the caller
  BadInput = 3,      // malformed or unsuitable mesh / file
  Numerical = 4,     // e.g. matrix not positive definite
  Cancelled = 5,     // a RunContext cancel flag was raised
  ResourceLimit = 6, // would exceed the memory limit
  Internal = 70,     // a bug in locus
};

// Where a failure happened, for callers that react to it without parsing the
// message (e.g. the factor-once update renames a submatrix column): the input
// vertex / row index and the factor column; -1 when not applicable.
struct LOCUS_API ErrorLocation {
  int64_t vertex = -1;
  int64_t column = -1;
};

class LOCUS_API Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message, ErrorLocation where = {})
      : std::runtime_error(message), code_(code), where_(where) {}
  ErrorCode code() const noexcept { return code_; }
  const ErrorLocation& where() const noexcept { return where_; }
  // Exit status the CLI uses for this error.
  int exit_status() const noexcept { return code_ == ErrorCode::ResourceLimit ? 3 : static_cast<int>(code_); }

 private:
  ErrorCode code_;
  ErrorLocation where_;
};

[[noreturn]] inline void fail(ErrorCode code, const std::string& message, ErrorLocation where = {}) {
  throw Error(code, message, where);
}

}  // namespace locus
LOCUS_API_END
