// The pool behind frnn::parallel_chunks (include/frnn/parallel.hpp).
//
// One pool per calling thread, its workers made on first use. A call publishes a job; the caller
// and every awake worker claim its chunks from one counter, and the call is over when the last
// chunk is finished, whoever ran it. A worker that wakes late finds no chunk and goes back to
// waiting: nobody waits for it. How threads wait is explained at spin_time below.
#include <pthread.h>
#include <sched.h>
#ifdef __linux__
#include <fcntl.h>
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cpu/cpu_spread.hpp"
#include "frnn/error.hpp"
#include "frnn/parallel.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace frnn {
namespace {
using clock = std::chrono::steady_clock;

// How a thread waits. First it spins for spin_time: a join usually ends, and the next step of a
// call usually starts, within microseconds. Then a caller waiting for its last chunks sleeps on
// a futex, so that a worker the scheduler has pushed aside can take its core. An idle worker
// spins on for up to idle_spin_time while the machine has a core to spare (on virtual machines
// waking a sleeping CPU costs tens of microseconds per step, and serial stretches of a few
// hundred microseconds between steps are common), and sleeps as soon as it has none.
constexpr auto spin_time = std::chrono::microseconds(50);
constexpr auto idle_spin_time = std::chrono::milliseconds(2);

// Whether no thread waits for a CPU: the kernel's count of runnable threads (the fourth field
// of /proc/loadavg, "running/total", which counts the caller too) is at most the number of
// CPUs this process may use. Where that cannot be read: false, so that nobody spins long.
bool core_to_spare() {
#ifdef __linux__
    struct proc_file {
        int fd = ::open("/proc/loadavg", O_RDONLY | O_CLOEXEC);
        ~proc_file() {
            if (fd >= 0) ::close(fd);
        }
    };
    thread_local const proc_file loadavg;
    static const long cpus = [] {
        cpu_set_t set;
        return sched_getaffinity(0, sizeof set, &set) == 0 ? long(CPU_COUNT(&set)) : 1L;
    }();
    char text[128];
    const ssize_t n = loadavg.fd >= 0 ? ::pread(loadavg.fd, text, sizeof text - 1, 0) : -1;
    if (n <= 0) return false;
    text[n] = '\0';
    const char* field = text;
    for (int spaces = 0; *field && spaces < 3; ++field) spaces += *field == ' ';
    const long running = std::strtol(field, nullptr, 10);
    return running > 0 && running <= cpus;
#else
    return false;
#endif
}

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

// Spins until done() is true or `how_long` has passed; returns done(). With `while_spare`, it
// also stops early when no core is to spare.
template <class Done>
bool spin_until(Done done, clock::duration how_long, bool while_spare = false) {
    const auto end = clock::now() + how_long;
    for (int round = 1;; ++round) {
        for (int i = 0; i < 64; ++i) {
            if (done()) return true;
            cpu_relax();
        }
        if (clock::now() >= end) return done();
        if (while_spare && round % 32 == 0 && !core_to_spare()) return done();
    }
}

// A word that threads can sleep on until it changes. Sleepers are counted so that a change
// costs a system call only when someone sleeps; both sides use sequentially consistent order,
// so a sleeper either sees the new value or is counted before the waker looks.
class wake_word {
public:
    std::uint32_t load() const { return value_.load(std::memory_order_acquire); }

    /// Waits until the value is no longer `old`: spins, then (an idle worker) spins on while
    /// nobody else wants the core, then sleeps.
    void wait_while(std::uint32_t old, bool idle = false) {
        const auto changed = [&] { return load() != old; };
        if (spin_until(changed, spin_time)) return;
        if (idle && core_to_spare() && spin_until(changed, idle_spin_time, true)) return;
        sleepers_.fetch_add(1);
        while (value_.load() == old) sleep_while(old);
        sleepers_.fetch_sub(1);
    }

    /// Stores a new value and wakes every thread waiting for a change.
    void set(std::uint32_t v) {
        value_.store(v);
        if (sleepers_.load() > 0) wake_all();
    }
    void increment() { set(value_.load() + 1); }

private:
#ifdef __linux__
    // The kernel compares the word before it sleeps: a change just before is not missed.
    void sleep_while(std::uint32_t old) {
        syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&value_), FUTEX_WAIT_PRIVATE, old, nullptr, nullptr, 0);
    }
    void wake_all() {
        syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&value_), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
    }
#else
    void sleep_while(std::uint32_t old) { value_.wait(old); }
    void wake_all() { value_.notify_all(); }
#endif
    static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
    std::atomic<std::uint32_t> value_{0};
    std::atomic<int> sleepers_{0};
};

// True while this thread runs a chunk: a parallel_chunks call from there runs serially.
thread_local bool inside_chunk = false;

// Keeps a worker off the CPUs of its job's other threads (see cpu_spread.hpp).
class cpu_spreader {
public:
    cpu_spreader() {
#ifdef __linux__
        if (sched_getaffinity(0, sizeof allowed_, &allowed_) != 0) CPU_ZERO(&allowed_);
#endif
    }

    /// Records where thread `me` of a job runs now: cpus[me] (see spread_mask).
    static void note_cpu(int me, std::atomic<int>* cpus) {
#ifdef __linux__
        const int cpu = sched_getcpu();
        if (cpus[me].load(std::memory_order_relaxed) != cpu) cpus[me].store(cpu, std::memory_order_relaxed);
#else
        static_cast<void>(me), static_cast<void>(cpus);
#endif
    }

    /// Moves worker `me` off its CPU when a thread before it in the job runs there too.
    void keep_apart(int me, std::atomic<int>* cpus, int threads) {
#ifdef __linux__
        cpu_set_t mask;
        if (detail::spread_mask(me, cpus, threads, allowed_, mask) && sched_setaffinity(0, sizeof mask, &mask) == 0)
            note_cpu(me, cpus);  // the kernel has moved this thread before returning
#else
        static_cast<void>(me), static_cast<void>(cpus), static_cast<void>(threads);
#endif
    }

private:
#ifdef __linux__
    cpu_set_t allowed_{};
#endif
};

// One call's work. Shared by the caller and the workers that joined; a worker may hold it after
// the call has returned, but then only finds the chunk counter exhausted and never touches
// `context`, which lived in the caller's frame.
struct job {
    void (*run)(void*, std::size_t, int) = nullptr;
    void* context = nullptr;
    std::size_t chunks = 0;
    int helpers;  // workers 1..helpers may join
    std::atomic<std::size_t> next{0}, finished{0};
    wake_word done;  // 1 once every chunk has finished
    std::atomic<bool> failed{false};
    std::mutex error_mutex;
    std::exception_ptr error;
    std::unique_ptr<std::atomic<int>[]> cpus;  // where thread 0..helpers ran its last chunk

    explicit job(int threads) : helpers(threads - 1), cpus(new std::atomic<int>[std::size_t(threads)]) {
        for (int i = 0; i < threads; ++i) cpus[i].store(-1, std::memory_order_relaxed);
    }

    /// Runs chunks until none is left. A worker passes its spreader (see cpu_spreader).
    void take_chunks(int worker, cpu_spreader* spreader = nullptr) {
        const bool outer = inside_chunk;
        inside_chunk = true;
        for (;;) {
            const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
            if (c >= chunks) break;
            cpu_spreader::note_cpu(worker, cpus.get());
            if (spreader) spreader->keep_apart(worker, cpus.get(), helpers + 1);
            if (!failed.load(std::memory_order_relaxed)) {
                try {
                    run(context, c, worker);
                } catch (...) {
                    const std::lock_guard lock(error_mutex);
                    if (!error) error = std::current_exception();
                    failed.store(true, std::memory_order_relaxed);
                }
            }
            if (finished.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) done.set(1);
        }
        inside_chunk = outer;
    }
};

// Counts forks, so that a child process does not use its parent's workers (it has none).
std::atomic<unsigned> forks{0};

class pool {
public:
    pool() : forks_seen_(forks.load()) {
        static std::once_flag registered;
        std::call_once(registered, [] { pthread_atfork(nullptr, nullptr, [] { forks.fetch_add(1); }); });
    }
    pool(const pool&) = delete;
    pool& operator=(const pool&) = delete;
    ~pool() {
        stopping_.store(true);
        generation_.increment();
        for (auto& w : workers_) w.join();
    }

    bool made_in_this_process() const { return forks_seen_ == forks.load(); }

    void run(std::size_t chunks, int threads, void (*body)(void*, std::size_t, int), void* context) {
        add_workers(std::size_t(threads - 1));
        auto j = std::make_shared<job>(std::min(threads, int(workers_.size()) + 1));
        j->run = body;
        j->context = context;
        j->chunks = chunks;
        cpu_spreader::note_cpu(0, j->cpus.get());  // before any worker looks
        publish(j);
        j->take_chunks(0);
        j->done.wait_while(0);
        publish(nullptr);
        if (j->error) std::rethrow_exception(j->error);
    }

private:
    void add_workers(std::size_t wanted) {
        try {
            workers_.reserve(wanted);
            while (workers_.size() < wanted) {
                // The generation now, not when the thread gets to run: a job published (or a
                // stop) in between must count as new to it.
                const int index = int(workers_.size()) + 1;
                const std::uint32_t seen = generation_.load();
                workers_.emplace_back([this, index, seen] { work(index, seen); });
            }
        } catch (...) {
            // Out of threads or memory: the call runs on the workers that exist.
        }
    }

    void publish(std::shared_ptr<job> j) {
        const bool wake = j != nullptr;
        {
            const std::lock_guard lock(mutex_);
            current_ = std::move(j);
        }
        if (wake) generation_.increment();
    }

    void work(int index, std::uint32_t seen) {
        cpu_spreader spreader;
        for (;;) {
            generation_.wait_while(seen, true);
            seen = generation_.load();
            if (stopping_.load()) return;
            std::shared_ptr<job> j;
            {
                const std::lock_guard lock(mutex_);
                j = current_;
            }
            if (j && index <= j->helpers) j->take_chunks(index, &spreader);
        }
    }

    unsigned forks_seen_;
    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::shared_ptr<job> current_;  // guarded by mutex_
    wake_word generation_;  // counts published jobs; changed only by the owning thread
    std::atomic<bool> stopping_{false};
};

pool& pool_of_this_thread() {
    thread_local std::unique_ptr<pool> p;
    // In a forked child the workers are gone: joining them would hang, so the old pool is left.
    if (p && !p->made_in_this_process()) static_cast<void>(p.release());
    if (!p) p = std::make_unique<pool>();
    return *p;
}

// A positive count from environment variable `name`; 0 when unset.
int thread_count_from(const char* name, bool strict) {
    const char* text = std::getenv(name);
    if (!text || !*text) return 0;
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    const bool whole = *end == '\0';
    if (value > 0 && value <= 1 << 16 && (whole || !strict)) return int(value);
    if (strict) throw error(std::string(name) + "='" + text + "' is not a thread count (expected 1 to 65536)");
    return 0;
}

}  // namespace

int default_thread_count() {
    if (const int n = thread_count_from("FRNN_NUM_THREADS", true)) return n;
    if (const int n = thread_count_from("OMP_NUM_THREADS", false)) return n;
    cpu_set_t cpus;
    if (sched_getaffinity(0, sizeof cpus, &cpus) == 0) return std::max(1, CPU_COUNT(&cpus));
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

namespace detail {

void run_chunks(std::size_t chunks, int threads, void (*run)(void*, std::size_t, int), void* context) {
    if (chunks == 0) return;
    threads = resolve_thread_count(threads);
    threads = int(std::min<std::size_t>(std::size_t(threads), chunks));
    if (threads == 1 || inside_chunk) {
        for (std::size_t c = 0; c < chunks; ++c) run(context, c, 0);
        return;
    }
    pool_of_this_thread().run(chunks, threads, run, context);
}

}  // namespace detail
}  // namespace frnn
