// Storage types that frnn::grid holds as members: internal to frnn, in a header of their own
// so that frnn/grid.hpp shows only what a user calls.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>

#include "frnn/buffer.hpp"

namespace frnn::detail {

/// Extra values after the last sorted coordinate, so vector loads never leave the array.
inline constexpr std::size_t coordinate_padding = 16;

/// Hashed grid: which of 32 table slots hold points (bit k for slot 32 w + k), and how many
/// slots before them do. An occupied slot's index among the occupied ones is one popcount away,
/// so the table stores a start only per occupied slot (4 bytes each, not 4 per slot).
struct occupied_slot_word {
    std::uint32_t bits;
    std::uint32_t before;
};

/// The inverse of a grid's permutation, computed on first use: most uses never need it, so the
/// build neither writes it nor keeps its 4 bytes per point. Safe to call concurrently.
class lazy_inverse {
public:
    lazy_inverse() = default;
    lazy_inverse(const lazy_inverse& other) { *this = other; }
    lazy_inverse& operator=(const lazy_inverse& other);
    /// The inverse of `perm`, computed with `threads` threads if not yet known.
    std::span<const std::uint32_t> get(std::span<const std::uint32_t> perm, int threads) const;
    /// Forgets the map after a rebuild; its memory is kept for the next use.
    void invalidate() { ready_.store(false, std::memory_order_release); }
    std::size_t capacity_bytes() const { return map_.capacity() * sizeof(std::uint32_t); }

private:
    mutable buffer<std::uint32_t> map_;
    mutable std::atomic<bool> ready_{false};
};

/// Memory a grid keeps between its builds for their scratch (the system may take it back in
/// between, see free_lazily). A copy of the grid starts without it.
template <class U = std::byte>
struct build_scratch {
    buffer<U> values;
    build_scratch() = default;
    build_scratch(const build_scratch&) {}
    build_scratch& operator=(const build_scratch&) { return *this; }
    build_scratch(build_scratch&&) = default;
    build_scratch& operator=(build_scratch&&) = default;
};

}  // namespace frnn::detail
