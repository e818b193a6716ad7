// frnn::buffer<T>: the array type of frnn's large results (neighbor lists) and grid storage.
//
// A std::vector with an allocator that (1) leaves new elements uninitialized when the vector
// grows, because frnn writes every element it hands out and zero-filling first would cost as
// much as the writes, and (2) on Linux asks for transparent huge pages for arrays of 2 MiB or
// more (when rounding up to whole huge pages wastes at most an eighth), which cuts the page
// faults of a fresh 100 MB neighbor list by a factor of 512.
// Growing a buffer yourself leaves the new elements unspecified, as numpy.empty does.
#pragma once
#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace frnn {

namespace detail {
void* allocate_large(std::size_t bytes);
void deallocate_large(void* p, std::size_t bytes) noexcept;
}  // namespace detail

template <class T>
struct buffer_allocator {
    using value_type = T;

    buffer_allocator() = default;
    template <class U>
    buffer_allocator(const buffer_allocator<U>&) noexcept {}

    T* allocate(std::size_t n) { return static_cast<T*>(detail::allocate_large(n * sizeof(T))); }
    void deallocate(T* p, std::size_t n) noexcept { detail::deallocate_large(p, n * sizeof(T)); }

    /// Default-initialization: no zero-fill for arithmetic types.
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }

    friend bool operator==(const buffer_allocator&, const buffer_allocator&) { return true; }
};

template <class T>
using buffer = std::vector<T, buffer_allocator<T>>;

}  // namespace frnn
