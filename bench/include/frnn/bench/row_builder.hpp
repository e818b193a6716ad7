// Neighbor counts and CSR lists assembled from a per-row visitor, for the baselines.
// Rows are split into one contiguous block per thread; each block fills its own buffer and the
// buffers are joined in row order, so the output is identical for any thread count. The
// buffers are frnn::buffer: from 2 MiB on they are mapped on their own and unmapped when
// freed. As std::vector they grew in each worker thread's heap, which malloc_trim does not
// shrink, and stayed resident into the next method's peak RSS (28 MiB after W1 at 262K).
// O(N + pairs) beyond the visits; memory: the lists twice at the peak (buffers + result).
// `visit` must be safe to call concurrently.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "frnn/buffer.hpp"
#include "frnn/csr.hpp"
#include "frnn/parallel.hpp"

namespace frnn::bench::detail {

// Runs body(block, first_row, end_row) for `threads` contiguous blocks of [0, n) in parallel;
// an exception thrown in a block is rethrown here.
template <class Body>
void for_row_blocks(std::size_t n, int threads, Body&& body) {
    threads = std::max(1, threads);
    const auto blocks = std::size_t(threads);
    parallel_chunks(blocks, threads, [&](std::size_t b, int) {
        body(int(b), n * b / blocks, n * (b + 1) / blocks);
    });
}

/// counts[i] = number of j passed by visit(i, emit) calling emit(j).
template <class Visit>
std::vector<std::uint32_t> counts_from_rows(std::size_t n, int threads, Visit&& visit) {
    std::vector<std::uint32_t> counts(n, 0);
    for_row_blocks(n, threads, [&](int, std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) {
            std::uint32_t c = 0;
            visit(i, [&c](std::uint32_t) { ++c; });
            counts[i] = c;
        }
    });
    return counts;
}

/// Row i of the result holds the j that visit(i, emit) passes to emit, in that order.
template <class T, class Visit>
csr<T> lists_from_rows(std::size_t n, int threads, Visit&& visit) {
    threads = std::max(1, threads);
    csr<T> out;
    out.offsets.assign(n + 1, 0);
    std::vector<buffer<std::uint32_t>> parts(static_cast<std::size_t>(threads));
    for_row_blocks(n, threads, [&](int b, std::size_t lo, std::size_t hi) {
        auto& part = parts[std::size_t(b)];
        for (std::size_t i = lo; i < hi; ++i) {
            const std::size_t before = part.size();
            visit(i, [&part](std::uint32_t j) { part.push_back(j); });
            out.offsets[i + 1] = part.size() - before;
        }
    });
    for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
    out.indices.resize(out.offsets[n]);
    for_row_blocks(n, threads, [&](int b, std::size_t lo, std::size_t) {
        auto& part = parts[std::size_t(b)];
        std::copy(part.begin(), part.end(), out.indices.begin() + std::ptrdiff_t(out.offsets[lo]));
        part = {};
    });
    return out;
}

}  // namespace frnn::bench::detail
