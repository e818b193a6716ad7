// The hit bits that the count sweep of a list keeps for its fill sweep (sweep.hpp), in one
// buffer cut into the sweeps' chunks. The fill reads each chunk once, in about the order of
// the chunks, so the memory of the chunks it is done with goes back to the system as it
// goes: the bits and the rows written so far then take about the memory of the rows alone.
#pragma once
#include <cstddef>
#include <mutex>
#include <numeric>
#include <vector>

#include "cpu/page_release.hpp"
#include "frnn/buffer.hpp"

namespace frnn::detail {

class hit_masks {
public:
    /// Room for chunks of the given sizes in bytes.
    explicit hit_masks(const std::vector<std::size_t>& chunk_bytes)
        : at_(chunk_bytes.size() + 1, 0), done_(chunk_bytes.size(), 0) {
        std::partial_sum(chunk_bytes.begin(), chunk_bytes.end(), at_.begin() + 1);
        bits_.resize(at_.back());
        released_ = bits_.data();
    }

    std::byte* chunk(std::size_t c) { return bits_.data() + at_[c]; }

    /// The fill sweep of chunk c is done with its bits: gives back the memory of the chunks
    /// before the first one that is not.
    void done(std::size_t c) {
        std::lock_guard<std::mutex> lock(mutex_);
        done_[c] = 1;
        const std::size_t before = first_open_;
        while (first_open_ < done_.size() && done_[first_open_]) ++first_open_;
        if (first_open_ > before) released_ = release_pages(released_, chunk(first_open_));
    }

private:
    buffer<std::byte> bits_;
    std::vector<std::size_t> at_;  ///< chunk c is bits_[at_[c], at_[c + 1])
    std::vector<char> done_;
    std::size_t first_open_ = 0;
    std::byte* released_ = nullptr;  ///< bits_ before it went back to the system
    std::mutex mutex_;
};

}  // namespace frnn::detail
