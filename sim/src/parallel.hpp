// Parallel loops of the solvers, on frnn's thread pool (frnn/parallel.hpp), with per-thread
// trace spans. Work is claimed in blocks of consecutive sorted particles (neighbouring cells),
// so each thread walks memory in order; results never depend on the split because each
// iteration writes only its own index.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

#include "frnn/parallel.hpp"
#include "frnn/sim/profiler.hpp"

namespace frnn::sim::detail {

/// Below this many items a loop runs on one thread: waking the pool costs more than it saves.
inline constexpr std::size_t min_parallel = 1024;
/// The same for loops doing a few flops per particle (integration), memory-bound anyway.
inline constexpr std::size_t min_parallel_light = 1 << 16;
/// Items per claimed block.
inline constexpr std::size_t block_items = 256;

/// Number of blocks of block_items covering n items.
inline std::size_t block_count(std::size_t n) { return (n + block_items - 1) / block_items; }

/// Calls f(block, begin, end) for the blocks of [0, n) on `threads` threads (one below `cutoff`).
template <class F>
void for_each_block(std::size_t n, int threads, std::size_t cutoff, F&& f) {
    parallel_chunks(block_count(n), n < cutoff ? 1 : threads, [&](std::size_t b, int) {
        f(b, b * block_items, std::min(n, (b + 1) * block_items));
    });
}

/// combine(...combine(init, value(0))..., value(n - 1)) as a parallel reduction; `combine` must
/// be associative and commutative with exact results (min, max, integer sums), so the result is
/// the same for any thread count.
template <class V, class Value, class Combine>
V reduce(std::size_t n, int threads, V init, Value&& value, Combine&& combine) {
    std::vector<V> partial(block_count(n), init);
    for_each_block(n, threads, min_parallel, [&](std::size_t b, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) partial[b] = combine(partial[b], value(i));
    });
    for (const V& p : partial) init = combine(init, p);
    return init;
}

template <class F>
void parallel_for(std::size_t n, int threads, profiler& prof, stage s, F&& f, std::size_t cutoff = min_parallel) {
    const double t_start = prof.now(), c_start = profiler::cpu_now();
    parallel_chunks(block_count(n), n < cutoff ? 1 : threads, [&](std::size_t b, int worker) {
        const double t0 = prof.tracing() ? prof.now() : 0;
        for (std::size_t i = b * block_items, end = std::min(n, (b + 1) * block_items); i < end; ++i) f(i);
        if (prof.tracing()) prof.span(s, worker, t0, prof.now());
    });
    prof.add(s, prof.now() - t_start);
    prof.add_cpu(s, profiler::cpu_now() - c_start);
}

/// Sequential-looking scope timed as a stage, spanning thread 0 in the trace.
template <class F>
void serial(profiler& prof, stage s, F&& f) {
    const double t0 = prof.now(), c0 = profiler::cpu_now();
    f();
    const double t1 = prof.now();
    prof.add(s, t1 - t0);
    prof.add_cpu(s, profiler::cpu_now() - c0);
    prof.span(s, 0, t0, t1);
}

}  // namespace frnn::sim::detail
