// locus::View<T> — a pointer and a count, the public headers' array argument.
//
// The library is C++20, but hosts such as DCC plugins build against the VFX
// Reference Platform, which is C++17 and has no std::span. The public headers
// (session.hpp, mesh.hpp and what they include) therefore take and return
// View<T> instead. It converts implicitly from a pointer and a size, a
// std::vector, a std::array, a C array and (under C++20) a std::span; under
// C++20 it is also a contiguous, borrowed range, so std::span<T> converts from
// it implicitly and library code keeps passing it to span-taking kernels.
// ConstView<T> is View<const T>. A View never owns its elements: like a span,
// it must not outlive the container it was made from.
#pragma once
#include <cstddef>
#include <iterator>
#include <type_traits>

#if __cplusplus >= 202002L && __has_include(<span>)
#include <ranges>
#include <span>
#define LOCUS_VIEW_HAS_SPAN 1
#endif

namespace locus {

template <class T>
class View {
  // Containers whose data() points to elements that T* may alias (the same
  // type up to adding const): std::vector, std::array, std::span, View.
  template <class C>
  using data_pointer_t = decltype(std::data(std::declval<C&>()));
  template <class C, class = void>
  struct compatible : std::false_type {};
  template <class C>
  struct compatible<C, std::void_t<data_pointer_t<C>, decltype(std::size(std::declval<C&>()))>>
      : std::is_convertible<std::remove_pointer_t<data_pointer_t<C>> (*)[], T (*)[]> {};
  // A temporary container may only be viewed read-only (as for std::span): a
  // mutable view of it would dangle at the end of the full expression. Views
  // and spans themselves are borrowed and may be temporaries.
  template <class C>
  static constexpr bool borrowed_v = std::is_lvalue_reference_v<C> || std::is_const_v<T>
#ifdef LOCUS_VIEW_HAS_SPAN
                                     || std::ranges::borrowed_range<C>
#endif
      ;

 public:
  using element_type = T;
  using value_type = std::remove_cv_t<T>;
  using size_type = std::size_t;
  using pointer = T*;
  using reference = T&;
  using iterator = T*;

  constexpr View() noexcept = default;
  constexpr View(T* data, std::size_t size) noexcept : data_(data), size_(size) {}
  template <std::size_t N>
  constexpr View(T (&array)[N]) noexcept : data_(array), size_(N) {}
  template <class C, std::enable_if_t<!std::is_same_v<std::remove_cv_t<std::remove_reference_t<C>>, View> &&
                                          compatible<std::remove_reference_t<C>>::value && borrowed_v<C>,
                                      int> = 0>
  constexpr View(C&& c) noexcept : data_(std::data(c)), size_(std::size(c)) {}

  constexpr T* data() const noexcept { return data_; }
  constexpr std::size_t size() const noexcept { return size_; }
  constexpr bool empty() const noexcept { return size_ == 0; }
  constexpr T& operator[](std::size_t i) const noexcept { return data_[i]; }
  constexpr T* begin() const noexcept { return data_; }
  constexpr T* end() const noexcept { return data_ + size_; }
  constexpr T& front() const noexcept { return data_[0]; }
  constexpr T& back() const noexcept { return data_[size_ - 1]; }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0;
};

template <class T>
using ConstView = View<const T>;

}  // namespace locus

#ifdef LOCUS_VIEW_HAS_SPAN
// A View is a borrowed range: std::span may be built from a temporary View.
namespace std::ranges {
template <class T>
inline constexpr bool enable_borrowed_range<locus::View<T>> = true;
}  // namespace std::ranges
#endif
