// Memory of frnn::buffer: huge-page-aligned blocks for large arrays (see frnn/buffer.hpp).
#include <cstdlib>
#include <new>

#include "frnn/buffer.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace frnn::detail {

namespace {
constexpr std::size_t huge_page = std::size_t(2) << 20;
constexpr std::size_t large = std::size_t(4) << 20;
}  // namespace

void* allocate_large(std::size_t bytes) {
    if (bytes < large) return ::operator new(bytes);
    const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
    void* p = std::aligned_alloc(huge_page, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: without it the memory still works
#endif
    return p;
}

void deallocate_large(void* p, std::size_t bytes) noexcept {
    if (bytes < large) ::operator delete(p);
    else std::free(p);
}

}  // namespace frnn::detail
