// The host's allocator for locus' large buffers (README "The
// allocator").
//
// Public (installed as locus/core/host_allocator.hpp): Mesh and CscMatrix
// hold their arrays in HostVector.
//
// A host (game engine, DCC plugin) hands locus malloc/free-style callbacks with
// locus_set_allocator; the buffers allocated through host_allocate() then come
// from them. What goes through here: every container typed with HostVector /
// HostAllocator / DefaultInitAllocator, which covers every block of 64 KB or
// more of a geodesic, log map or CVT call (ctest allocator_unrouted), and
// every allocation METIS makes (cmake/metis.cmake renames its
// malloc/calloc/realloc/free to kernels/src/order/metis_memory.cpp). What does
// not: OpenBLAS' own buffer pool (docs/shipping.md).
//
// Each block carries a 32-byte header naming the callbacks that allocated it,
// so a block is always freed by the allocator that made it, even when the host
// switches allocators while locus still holds blocks (caches of a Session).
#pragma once
#include <algorithm>
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

using HostAllocFn = void* (*)(std::size_t size, void* user);
using HostFreeFn = void (*)(void* ptr, void* user);

// Both callbacks, or neither (nullptr, nullptr: back to the C library's
// malloc/free). Thread-safe; blocks allocated before keep their callbacks.
LOCUS_API void set_host_allocator(HostAllocFn alloc, HostFreeFn free, void* user) noexcept;

// `bytes` from the current allocator, 16-byte aligned; nullptr when it has none to give.
LOCUS_API void* host_allocate_nothrow(std::size_t bytes) noexcept;
// The same, throwing std::bad_alloc instead of returning nullptr.
LOCUS_API void* host_allocate(std::size_t bytes);
// Frees a block of host_allocate*; nullptr is a no-op. A pointer that did not
// come from host_allocate* (no header) goes to the C library's free().
LOCUS_API void host_deallocate(void* p) noexcept;
// Size in bytes the block was allocated with (for realloc).
LOCUS_API std::size_t host_allocation_size(const void* p) noexcept;

}  // namespace locus
LOCUS_API_END

// Hidden like the rest of locus' types: the vector instantiations over it stay
// out of the shared library's exports (the host instantiates its own).
namespace locus {

// A std allocator over host_allocate: containers of any element type up to
// 16-byte alignment. Stateless; any instance frees any block (the header knows
// its callbacks).
template <typename T>
struct HostAllocator {
  static_assert(alignof(T) <= 16, "host allocations are 16-byte aligned");
  using value_type = T;
  using is_always_equal = std::true_type;
  HostAllocator() noexcept = default;
  template <typename U>
  HostAllocator(const HostAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / (2 * sizeof(T))) throw std::bad_array_new_length();
    return static_cast<T*>(host_allocate(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept { host_deallocate(p); }
  template <typename U>
  bool operator==(const HostAllocator<U>&) const noexcept { return true; }
  template <typename U>
  bool operator!=(const HostAllocator<U>&) const noexcept { return false; }
};

// A vector in the host's memory: the arrays of Mesh and CscMatrix, the derived
// mesh and symbolic structures, workspaces and per-query buffers. A std::vector
// with the host's allocator, plus the conversions a caller holding std::vectors
// needs: it is built (and so assigned) from a std::vector by copying, and
// converts back explicitly (std::vector<T> v(host_vector)).
template <typename T>
class HostVector : public std::vector<T, HostAllocator<T>> {
  using Base = std::vector<T, HostAllocator<T>>;

 public:
  using Base::Base;
  HostVector() = default;
  HostVector(const Base& v) : Base(v) {}  // NOLINT: a std::vector<T, HostAllocator<T>> is one
  HostVector(Base&& v) noexcept : Base(std::move(v)) {}  // NOLINT
  HostVector(const std::vector<T>& v) : Base(v.begin(), v.end()) {}  // NOLINT: implicit by design
  explicit operator std::vector<T>() const { return std::vector<T>(this->begin(), this->end()); }
};

// Element-wise comparison with a std::vector (found by argument-dependent
// lookup).
template <typename T>
bool operator==(const HostVector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}
template <typename T>
bool operator==(const std::vector<T>& a, const HostVector<T>& b) {
  return b == a;
}
template <typename T>
bool operator!=(const HostVector<T>& a, const std::vector<T>& b) {
  return !(a == b);
}
template <typename T>
bool operator!=(const std::vector<T>& a, const HostVector<T>& b) {
  return !(b == a);
}

}  // namespace locus
