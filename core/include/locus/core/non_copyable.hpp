// A base for scope guards and other objects with an identity (a commit group,
// a BLAS thread-count scope, a METIS random scope): copying one would run its
// release twice. Not installed.
#pragma once

namespace locus {

class NonCopyable {
 protected:
  NonCopyable() = default;
  ~NonCopyable() = default;

 public:
  NonCopyable(const NonCopyable&) = delete;
  NonCopyable& operator=(const NonCopyable&) = delete;
};

}  // namespace locus
