// Threaded execution of the core's steps on frnn's pool (frnn/parallel.hpp). Work is cut into
// chunks whose results are combined in chunk order, so every output is identical for any thread
// count.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "frnn/parallel.hpp"

namespace frnn::detail {


/// Splits [0, n) into `parts` contiguous chunks; chunk c is [bound(c), bound(c+1)).
inline std::size_t chunk_bound(std::size_t n, std::size_t parts, std::size_t c) {
    return n / parts * c + n % parts * c / parts;
}

/// Runs f(chunk, begin, end) on each of `parts` chunks of [0, n) with `threads` threads.
/// Chunks are handed out dynamically: callers must not depend on which thread runs which.
template <class F>
void for_each_chunk(std::size_t n, std::size_t parts, int threads, F&& f) {
    parallel_chunks(parts, std::max(threads, 1), [&](std::size_t c, int) {
        f(c, chunk_bound(n, parts, c), chunk_bound(n, parts, c + 1));
    });
}

/// How many chunks to cut n items into: enough for load balance, none tiny.
inline std::size_t chunk_count(std::size_t n, int threads, std::size_t min_chunk = 4096) {
    if (threads <= 1) return 1;
    return std::clamp<std::size_t>(n / min_chunk, 1, std::size_t(threads) * 16);
}

/// In-place exclusive prefix sum of data[0..n); returns the total.
template <class U>
U exclusive_scan(U* data, std::size_t n, int threads) {
    const std::size_t parts = chunk_count(n, threads, 1 << 16);
    if (parts == 1) {
        U sum = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const U v = data[i];
            data[i] = sum;
            sum += v;
        }
        return sum;
    }
    std::vector<U> partial(parts + 1, 0);
    for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
        U sum = 0;
        for (std::size_t i = b; i < e; ++i) sum += data[i];
        partial[c + 1] = sum;
    });
    for (std::size_t c = 0; c < parts; ++c) partial[c + 1] += partial[c];
    for_each_chunk(n, parts, threads, [&](std::size_t c, std::size_t b, std::size_t e) {
        U sum = partial[c];
        for (std::size_t i = b; i < e; ++i) {
            const U v = data[i];
            data[i] = sum;
            sum += v;
        }
    });
    return partial[parts];
}

}  // namespace frnn::detail
