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

std::size_t rounded_to_huge_pages(std::size_t bytes) { return (bytes + huge_page - 1) / huge_page * huge_page; }

// Huge pages from one up, when rounding up to whole huge pages wastes at most an eighth.
bool large(std::size_t bytes) {
    return bytes >= huge_page && rounded_to_huge_pages(bytes) - bytes <= bytes / 8;
}
}  // namespace

void* allocate_large(std::size_t bytes) {
    if (!large(bytes)) return ::operator new(bytes);
    const std::size_t rounded = rounded_to_huge_pages(bytes);
    void* p = std::aligned_alloc(huge_page, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: without it the memory still works
#endif
    return p;
}

void deallocate_large(void* p, std::size_t bytes) noexcept {
    if (!large(bytes)) ::operator delete(p);
    else std::free(p);
}

}  // namespace frnn::detail
