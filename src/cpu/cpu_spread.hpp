// Where a pool worker may run: off the CPUs of its job's other threads (src/cpu/thread_pool.cpp).
//
// When another process takes a core, the kernel often places a woken worker on its caller's CPU
// (that CPU looks the less loaded one), and then two threads of one call share a core while the
// busy process has the other to itself, until the load balancer moves one of them milliseconds
// later (docs/DESIGN.md's table of alternatives has the figures without this rule).
// So a worker that finds a thread before it in its job (the caller is thread 0) on its own CPU
// narrows its own affinity (never the caller's) to the CPUs it was allowed minus those of the
// job's other threads. Only when the job has no more threads than there are CPUs.
#pragma once
#ifdef __linux__
#include <sched.h>

#include <atomic>

namespace frnn::detail {

/// Whether thread `me` of a job should leave its CPU; then `mask` is where it may go.
/// cpus[i] is the CPU that thread i of the job ran its last chunk on (-1: none yet); `allowed`
/// is the affinity the worker started with.
inline bool spread_mask(int me, const std::atomic<int>* cpus, int threads, const cpu_set_t& allowed,
                        cpu_set_t& mask) {
    const int cpu = cpus[me].load(std::memory_order_relaxed);
    if (cpu < 0 || threads > CPU_COUNT(&allowed)) return false;
    bool shared = false;
    for (int i = 0; i < me && !shared; ++i) shared = cpus[i].load(std::memory_order_relaxed) == cpu;
    if (!shared) return false;
    mask = allowed;
    for (int i = 0; i < threads; ++i) {
        const int other = cpus[i].load(std::memory_order_relaxed);
        if (i != me && other >= 0 && other < CPU_SETSIZE) CPU_CLR(other, &mask);
    }
    return CPU_COUNT(&mask) > 0;
}

}  // namespace frnn::detail
#endif
