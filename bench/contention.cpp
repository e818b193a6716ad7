#include "frnn/bench/contention.hpp"

#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <new>

#include "frnn/error.hpp"

namespace frnn::bench {
namespace {

enum : int { quiet_state = 0, busy_state = 1, stop_state = 2 };

// One stretch of busy work, a few tens of microseconds: short enough that quiet() is not kept
// waiting, long enough that publishing the count costs nothing. volatile keeps the loop.
constexpr std::uint64_t chunk = 1 << 14;
std::uint64_t spin_chunk() {
    volatile std::uint64_t x = 0;
    for (std::uint64_t i = 0; i < chunk; ++i) x = x + 1;
    return chunk;
}

// The whole life of a child: only async-signal-safe calls (the parent may have other threads,
// whose locks the child inherits held), never a return into the parent's code, no atexit.
[[noreturn]] void child_loop(std::atomic<std::uint64_t>& n, pid_t parent) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(0);  // the parent died before prctl took effect
    ::kill(::getpid(), SIGSTOP);             // start quiet; the parent waits for this stop
    for (;;) n.fetch_add(spin_chunk(), std::memory_order_relaxed);
}

bool stopped(int status) { return WIFSTOPPED(status); }
bool continued(int status) { return WIFCONTINUED(status); }

}  // namespace

contention::contention(int k, mode m) : k_(k), mode_(m) {
    if (k < 1 || k > 64) throw error("contention: K = " + std::to_string(k) + " busy threads or processes; expected 1 to 64");
    // Shared, so that children can publish their counts (threads could use plain memory).
    void* mem = ::mmap(nullptr, sizeof(counter) * std::size_t(k), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (mem == MAP_FAILED) throw error(std::string("contention: mmap failed: ") + std::strerror(errno));
    counters_ = static_cast<counter*>(mem);
    for (int i = 0; i < k; ++i) new (&counters_[i]) counter;
    try {
        if (m == mode::threads)
            start_threads();
        else
            start_children();
    } catch (...) {
        shut_down();
        throw;
    }
}

contention::~contention() { shut_down(); }

void contention::start_threads() {
    for (int i = 0; i < k_; ++i) threads_.emplace_back([this, i] { spin_thread(std::size_t(i)); });
}

void contention::spin_thread(std::size_t k) {
    for (;;) {
        const int s = state_.load();
        if (s == stop_state) return;
        if (s == quiet_state) {
            state_.wait(quiet_state);
            continue;
        }
        spinning_.fetch_add(1);
        spinning_.notify_all();
        // seq_cst loads: a thread that enters after quiet() saw no thread spinning sees quiet here.
        while (state_.load() == busy_state) counters_[k].n.fetch_add(spin_chunk(), std::memory_order_relaxed);
        spinning_.fetch_sub(1);
        spinning_.notify_all();
    }
}

void contention::start_children() {
    const pid_t parent = ::getpid();
    for (int i = 0; i < k_; ++i) {
        const pid_t pid = ::fork();
        if (pid < 0) throw error(std::string("contention: fork failed: ") + std::strerror(errno));
        if (pid == 0) child_loop(counters_[i].n, parent);
        pids_.push_back(pid);
    }
    signal_children(0, WUNTRACED, stopped, "stopping");
}

// Sends `sig` (0: none) to every child, then waits until each reports the state `reached`
// tests. A child that ended is reaped, dropped from pids_ (so its pid, which the system may
// reuse, is never signalled again) and reported with an exception.
void contention::signal_children(int sig, int wait_options, bool (*reached)(int status), const char* what) {
    if (sig != 0)
        for (pid_t pid : pids_) ::kill(pid, sig);
    for (std::size_t i = 0; i < pids_.size(); ++i) {
        const pid_t pid = pids_[i];
        for (;;) {
            int status = 0;
            const pid_t r = ::waitpid(pid, &status, wait_options);
            if (r < 0 && errno == EINTR) continue;
            if (r == pid && reached(status)) break;
            if (r < 0 || WIFEXITED(status) || WIFSIGNALED(status)) {
                pids_.erase(pids_.begin() + std::ptrdiff_t(i));
                throw error("contention: busy child " + std::to_string(pid) + " ended instead of " + what);
            }
        }
    }
}

void contention::busy() {
    if (busy_) return;
    if (mode_ == mode::processes) {
        signal_children(SIGCONT, WCONTINUED, continued, "continuing");
    } else {
        state_.store(busy_state);
        state_.notify_all();
        for (int n = spinning_.load(); n != k_; n = spinning_.load()) spinning_.wait(n);
    }
    busy_ = true;
}

void contention::quiet() {
    if (!busy_) return;
    if (mode_ == mode::processes) {
        signal_children(SIGSTOP, WUNTRACED, stopped, "stopping");
    } else {
        state_.store(quiet_state);
        for (int n = spinning_.load(); n != 0; n = spinning_.load()) spinning_.wait(n);
    }
    busy_ = false;
}

void contention::shut_down() noexcept {
    state_.store(stop_state);
    state_.notify_all();
    for (auto& t : threads_) t.join();
    threads_.clear();
    for (pid_t pid : pids_)
        if (pid > 0) ::kill(pid, SIGKILL);  // never 0 or -1: those name whole process groups
    for (pid_t pid : pids_)
        while (pid > 0 && ::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
        }
    pids_.clear();
    if (counters_) ::munmap(counters_, sizeof(counter) * std::size_t(k_));
    counters_ = nullptr;
}

std::uint64_t contention::iterations() const {
    std::uint64_t sum = 0;
    for (int i = 0; i < k_; ++i) sum += counters_[i].n.load(std::memory_order_relaxed);
    return sum;
}

std::string contention::describe() const {
    const std::string n = std::to_string(k_);
    if (mode_ == mode::threads) return n + (k_ == 1 ? " busy thread" : " busy threads") + " in this process";
    return n + (k_ == 1 ? " busy child process" : " busy child processes");
}

std::string autogroup_scheduling() {
    std::ifstream in("/proc/sys/kernel/sched_autogroup_enabled");
    int on = -1;
    if (!(in >> on)) return "unknown";
    return on == 1 ? "on" : on == 0 ? "off" : "unknown";
}

}  // namespace frnn::bench
