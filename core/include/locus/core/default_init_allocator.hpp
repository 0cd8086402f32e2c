// An allocator whose value-less construct() leaves doubles uninitialized, so a
// factor's storage is not zeroed (and page-faulted) by one thread up front:
// each supernode's task zeroes and touches its own block, in parallel. The
// memory comes from the host's allocator (host_allocator.hpp) by default.
#pragma once
#include <memory>
#include <type_traits>
#include <utility>

#include "locus/core/host_allocator.hpp"

namespace locus {

template <typename T, typename Base = HostAllocator<T>>
class DefaultInitAllocator : public Base {
  using traits = std::allocator_traits<Base>;

 public:
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename traits::template rebind_alloc<U>>;
  };
  using Base::Base;
  DefaultInitAllocator() = default;
  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    traits::construct(static_cast<Base&>(*this), p, std::forward<Args>(args)...);
  }
};

}  // namespace locus
