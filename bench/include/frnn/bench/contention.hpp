// A load generator for measuring speed under load (`frnn bench --contend`, `frnn sim
// --contend`): K busy-looping threads in this process, or K busy-looping child processes, that
// take cores away from the code being measured while they are switched on. It starts quiet;
// busy() and quiet() switch it and return once the switch has happened (threads spinning or
// parked; children continued or stopped, confirmed by waitpid). Quiet threads sleep on an
// atomic wait; quiet children are stopped with SIGSTOP, so neither uses a core.
//
// Children are forked at construction and run nothing but a busy loop (no allocation, no stdio),
// ended with SIGKILL by the destructor, which also reaps them; a child also dies with SIGKILL
// when the thread that forked it ends (PR_SET_PDEATHSIG), so construct the object on a thread
// that outlives it. Job control (Ctrl-Z, fg) during a measurement wakes stopped children and
// disturbs it. Linux only.
//
// Thread safety: busy(), quiet() and the destructor from one thread (the owner); iterations()
// from any thread.
#pragma once
#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

namespace frnn::bench {

class contention {
public:
    enum class mode { threads, processes };

    /// K busy threads or child processes, 1 <= K <= 64, quiet. Throws frnn::error when K is out
    /// of range or a thread or child cannot be started (those already started are ended).
    contention(int k, mode m);
    ~contention();
    contention(const contention&) = delete;
    contention& operator=(const contention&) = delete;

    /// Switches the load on: returns when every thread spins / every child has continued.
    void busy();
    /// Switches the load off: returns when every thread has left its loop / every child is stopped.
    void quiet();
    bool is_busy() const { return busy_; }

    /// Busy-loop iterations done so far by all threads or children together (a child publishes
    /// its count in memory shared with this process). Grows only while busy.
    std::uint64_t iterations() const;
    /// The children's process ids (empty in thread mode).
    const std::vector<pid_t>& children() const { return pids_; }
    /// "1 busy thread in this process", "2 busy child processes", ...
    std::string describe() const;

private:
    struct alignas(64) counter {
        std::atomic<std::uint64_t> n{0};
    };
    void spin_thread(std::size_t k);
    void start_children();
    void start_threads();
    void shut_down() noexcept;
    void signal_children(int sig, int wait_options, bool (*reached)(int status), const char* what);

    int k_;
    mode mode_;
    bool busy_ = false;
    counter* counters_ = nullptr;  // k_ counters; shared with the children in process mode
    std::vector<pid_t> pids_;
    std::vector<std::thread> threads_;
    std::atomic<int> state_{0};     // thread mode: 0 quiet, 1 busy, 2 stop
    std::atomic<int> spinning_{0};  // thread mode: threads inside their busy loop
};

/// Whether the kernel's autogroup scheduling is on: it shares CPU time between sessions first,
/// so a busy process started from another terminal takes less from this one than its thread
/// count suggests, while the children of a contention (same session) compete like threads.
/// "on", "off", or "unknown" when /proc/sys/kernel/sched_autogroup_enabled cannot be read.
std::string autogroup_scheduling();

}  // namespace frnn::bench
