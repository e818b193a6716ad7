// frnn's threads. Every parallel step of the library runs on a small pool of worker threads
// owned by the thread that calls it; the simulation and the Python module run their own loops on
// the same pool, and so can an application, so that its loops and frnn's never compete.
//
// Why a pool of its own rather than OpenMP: a call returns as soon as its chunks are done. It
// never waits for a worker that the operating system has not scheduled (such a worker simply
// finds no chunk left), and a thread stops spinning as soon as the scheduler preempts it: idle
// workers spin for up to 2 ms only while nobody else wants their core, then sleep. On a machine
// shared with another busy process, OpenMP's fork-join barriers wait for every thread of the team
// at the end of every parallel loop, and its spinning threads hold cores the others need.
//
// The pool's workers keep off the CPUs that the other threads of their call run on, by
// narrowing their own CPU affinity (never the caller's) when the call has no more threads than
// CPUs: under load the kernel tends to put a woken worker on its caller's CPU.
//
// Thread safety: any number of threads may call parallel_chunks at once; each caller gets its
// own workers (made on first use, ended with the calling thread). A call made from inside a
// chunk runs its chunks on the calling thread, one after another.
#pragma once
#include <cstddef>
#include <memory>
#include <type_traits>

namespace frnn {

/// Threads a call asking for 0 uses: FRNN_NUM_THREADS if set to a positive number, else
/// OMP_NUM_THREADS (its first number; cluster job launchers set it), else the number of CPUs
/// this process may run on.
int default_thread_count();
/// The rule for every `threads` setting of frnn: `requested` if positive, else
/// default_thread_count().
inline int resolve_thread_count(int requested) { return requested > 0 ? requested : default_thread_count(); }

namespace detail {
/// The pool's entry point behind parallel_chunks: run(context, chunk, worker) for each chunk.
void run_chunks(std::size_t chunks, int threads, void (*run)(void*, std::size_t, int), void* context);
}  // namespace detail

/// Calls body(chunk, worker) once for every chunk in [0, chunks), on at most `threads` threads
/// (0: default_thread_count()), the calling thread included; returns when all have run.
/// Chunks are claimed one at a time in increasing order by whichever thread is free, so results
/// must not depend on which thread runs which chunk: combine per-chunk results in chunk order.
/// `worker` is in [0, threads) and no two threads run with the same one at once: index per-thread
/// scratch with it. If a body throws, chunks not yet started are skipped and the first exception
/// is rethrown once every started chunk has finished.
template <class Body>
void parallel_chunks(std::size_t chunks, int threads, Body&& body) {
    using callable = std::remove_reference_t<Body>;
    auto run = [](void* context, std::size_t chunk, int worker) { (*static_cast<callable*>(context))(chunk, worker); };
    detail::run_chunks(chunks, threads, run, const_cast<void*>(static_cast<const void*>(std::addressof(body))));
}

}  // namespace frnn
