// Giving back the memory of a large array's part that is no longer needed.
#pragma once
#include <cstddef>

namespace frnn::detail {

/// Returns to the system the whole huge pages (2 MiB) inside [begin, end) of a block from
/// allocate_large, whose contents are not read again: they read as zero afterwards. Returns
/// the end of what it gave back, or begin when that was nothing (or the system offers no
/// such call).
std::byte* release_pages(std::byte* begin, std::byte* end) noexcept;

/// Lets the system take back the whole huge pages inside [begin, end) of a block from
/// allocate_large when it needs memory, but keeps them until then: their contents become
/// unspecified, and writing them again costs nothing while they are still there (scratch
/// kept between uses). Does nothing where the system offers no such call.
void free_lazily(std::byte* begin, std::byte* end) noexcept;

}  // namespace frnn::detail
