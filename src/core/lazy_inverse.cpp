// The grid's original -> sorted map, built on first use (see detail::lazy_inverse).
#include <mutex>

#include "cpu/parallel.hpp"
#include "frnn/grid.hpp"

namespace frnn::detail {
namespace {
// One lock for every grid: maps are computed rarely, and a grid stays small without a mutex.
std::mutex& inverse_mutex() {
    static std::mutex m;
    return m;
}
}  // namespace

lazy_inverse& lazy_inverse::operator=(const lazy_inverse& other) {
    if (this == &other) return *this;
    std::lock_guard lock(inverse_mutex());
    const bool ready = other.ready_.load(std::memory_order_acquire);
    if (ready) map_ = other.map_;
    ready_.store(ready, std::memory_order_release);
    return *this;
}

std::span<const std::uint32_t> lazy_inverse::get(std::span<const std::uint32_t> perm, int threads) const {
    if (!ready_.load(std::memory_order_acquire)) {
        std::lock_guard lock(inverse_mutex());
        if (!ready_.load(std::memory_order_relaxed)) {
            map_.resize(perm.size());
            const std::size_t n = perm.size();
            for_each_chunk(n, chunk_count(n, threads, 1 << 15), threads, [&](std::size_t, std::size_t b, std::size_t e) {
                for (std::size_t s = b; s < e; ++s) map_[perm[s]] = std::uint32_t(s);
            });
            ready_.store(true, std::memory_order_release);
        }
    }
    return {map_.data(), perm.size()};
}

}  // namespace frnn::detail
