// Memory of frnn::buffer: huge-page-aligned blocks for large arrays (see frnn/buffer.hpp).
#include <cstdint>
#include <cstdlib>
#include <new>

#include "cpu/page_release.hpp"
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
#if defined(__linux__)
    // Mapped directly rather than taken from the heap, so that freeing it gives the memory back
    // at once (the heap keeps freed blocks resident). Over-mapped by one huge page, then trimmed
    // to a huge-page boundary.
    void* raw = mmap(nullptr, rounded + huge_page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto begin = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t start = (begin + huge_page - 1) / huge_page * huge_page;
    if (start > begin) munmap(raw, start - begin);
    const std::uintptr_t tail = begin + rounded + huge_page - (start + rounded);
    if (tail > 0) munmap(reinterpret_cast<void*>(start + rounded), tail);
    void* p = reinterpret_cast<void*>(start);
#if defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: without it the memory still works
#endif
    return p;
#else
    void* p = std::aligned_alloc(huge_page, rounded);
    if (!p) throw std::bad_alloc();
    return p;
#endif
}

void deallocate_large(void* p, std::size_t bytes) noexcept {
    if (!large(bytes)) {
        ::operator delete(p);
        return;
    }
#if defined(__linux__)
    munmap(p, rounded_to_huge_pages(bytes));
#else
    std::free(p);
#endif
}

namespace {
/// madvise(advice) over the whole huge pages inside [begin, end); the end of that range if the
/// call succeeded, else begin.
[[maybe_unused]] std::byte* advise_huge_pages(std::byte* begin, std::byte* end, int advice) noexcept {
#if defined(__linux__)
    const std::uintptr_t first = (reinterpret_cast<std::uintptr_t>(begin) + huge_page - 1) / huge_page * huge_page;
    const std::uintptr_t last = reinterpret_cast<std::uintptr_t>(end) / huge_page * huge_page;
    if (last > first && madvise(reinterpret_cast<void*>(first), last - first, advice) == 0)
        return begin + (last - reinterpret_cast<std::uintptr_t>(begin));
#else
    (void)end, (void)advice;
#endif
    return begin;
}
}  // namespace

std::byte* release_pages(std::byte* begin, std::byte* end) noexcept {
#if defined(__linux__) && defined(MADV_DONTNEED)
    return advise_huge_pages(begin, end, MADV_DONTNEED);
#else
    (void)end;
    return begin;
#endif
}

void free_lazily(std::byte* begin, std::byte* end) noexcept {
#if defined(__linux__) && defined(MADV_FREE)
    advise_huge_pages(begin, end, MADV_FREE);
#else
    (void)begin, (void)end;
#endif
}

}  // namespace frnn::detail
