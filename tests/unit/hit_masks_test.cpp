// The store of kept hit bits: memory goes back to the system only for chunks whose fill is
// done, and only up to the first chunk that is not, whatever the order in which they finish.
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "core/hit_masks.hpp"

namespace {

using frnn::detail::hit_masks;

// Chunks of odd sizes of a few huge pages, so that chunk borders fall inside pages.
const std::vector<std::size_t> chunk_bytes = {3'000'001, 5'500'003, 4'194'304, 2'999'999, 7'000'017};

std::byte pattern(std::size_t c, std::size_t i) { return std::byte((c * 131 + i * 7 + 1) % 251 + 1); }

void write_chunk(hit_masks& store, std::size_t c) {
    std::byte* p = store.chunk(c);
    for (std::size_t i = 0; i < chunk_bytes[c]; ++i) p[i] = pattern(c, i);
}

bool chunk_intact(hit_masks& store, std::size_t c) {
    const std::byte* p = store.chunk(c);
    for (std::size_t i = 0; i < chunk_bytes[c]; ++i)
        if (p[i] != pattern(c, i)) return false;
    return true;
}

TEST(hit_masks, chunks_not_done_keep_their_bits_whatever_order_the_others_finish_in) {
    const std::vector<std::vector<std::size_t>> orders = {{0, 1, 2, 3, 4}, {4, 3, 2, 1, 0}, {1, 3, 0, 4, 2}, {2, 0, 1, 4, 3}};
    for (const auto& order : orders) {
        hit_masks store(chunk_bytes);
        for (std::size_t c = 0; c < chunk_bytes.size(); ++c) write_chunk(store, c);
        std::vector<bool> done(chunk_bytes.size(), false);
        for (std::size_t c : order) {
            store.done(c);
            done[c] = true;
            for (std::size_t other = 0; other < chunk_bytes.size(); ++other) {
                if (done[other]) continue;
                EXPECT_TRUE(chunk_intact(store, other)) << "chunk " << other << " after done(" << c << ")";
            }
        }
    }
}

TEST(hit_masks, chunks_sit_end_to_end_in_one_buffer) {
    hit_masks store(chunk_bytes);
    for (std::size_t c = 0; c + 1 < chunk_bytes.size(); ++c) EXPECT_EQ(store.chunk(c + 1) - store.chunk(c), std::ptrdiff_t(chunk_bytes[c]));
    for (std::size_t c = 0; c < chunk_bytes.size(); ++c) write_chunk(store, c);
    for (std::size_t c = 0; c < chunk_bytes.size(); ++c) EXPECT_TRUE(chunk_intact(store, c));
}

}  // namespace
