// Parallel loops of the solvers, with per-thread trace spans. Work is split statically into
// contiguous ranges of sorted particles (neighbouring cells), so each thread walks memory in
// order; results never depend on the split because each iteration writes only its own index.
#pragma once
#include <omp.h>

#include <cstddef>

#include "frnn/sim/profiler.hpp"

namespace frnn::sim::detail {

/// Below this many items a loop runs on one thread: waking a team costs more than it saves.
inline constexpr std::size_t min_parallel = 1024;
/// The same for loops doing a few flops per particle (integration), memory-bound anyway.
inline constexpr std::size_t min_parallel_light = 1 << 16;

template <class F>
void parallel_for(std::size_t n, int threads, profiler& prof, stage s, F&& f, std::size_t cutoff = min_parallel) {
    const double t_start = prof.now(), c_start = profiler::cpu_now();
#pragma omp parallel num_threads(n < cutoff ? 1 : threads)
    {
        const double t0 = prof.tracing() ? prof.now() : 0;
#pragma omp for schedule(dynamic, 256) nowait
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) f(std::size_t(i));
        if (prof.tracing()) prof.span(s, omp_get_thread_num(), t0, prof.now());
    }
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
