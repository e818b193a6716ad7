// Where a pool worker goes when it shares a CPU with a thread before it in its job
// (src/cpu/cpu_spread.hpp): off every CPU the job's other threads use, never onto none, and
// only while the job has no more threads than CPUs. Then a live call: a worker that starts on
// its caller's CPU leaves it.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <initializer_list>
#include <vector>

#include "cpu/cpu_spread.hpp"
#include "frnn/parallel.hpp"

namespace {

using frnn::detail::spread_mask;

cpu_set_t cpus_of(std::initializer_list<int> list) {
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int c : list) CPU_SET(c, &set);
    return set;
}

struct job_cpus {
    std::vector<std::atomic<int>> cpus;
    explicit job_cpus(std::initializer_list<int> list) : cpus(list.size()) {
        int i = 0;
        for (int c : list) cpus[std::size_t(i++)].store(c);
    }
    int threads() const { return int(cpus.size()); }
};

TEST(CpuSpread, AWorkerOnItsCallersCpuLeavesForTheOthers) {
    const job_cpus job{3, 3};
    cpu_set_t mask;
    ASSERT_TRUE(spread_mask(1, job.cpus.data(), job.threads(), cpus_of({0, 1, 2, 3}), mask));
    EXPECT_TRUE(CPU_EQUAL(&mask, &static_cast<const cpu_set_t&>(cpus_of({0, 1, 2}))));
}

TEST(CpuSpread, ItAvoidsEveryOtherThreadOfTheJob) {
    const job_cpus job{0, 5, 0, -1};  // thread 2 shares CPU 0 with the caller; thread 3 has not run
    cpu_set_t mask;
    ASSERT_TRUE(spread_mask(2, job.cpus.data(), job.threads(), cpus_of({0, 1, 2, 3, 4, 5, 6, 7}), mask));
    EXPECT_TRUE(CPU_EQUAL(&mask, &static_cast<const cpu_set_t&>(cpus_of({1, 2, 3, 4, 6, 7}))));
}

TEST(CpuSpread, OnlyTheLaterOfTwoThreadsOnACpuMoves) {
    const job_cpus job{1, 4, 4};
    cpu_set_t mask;
    EXPECT_FALSE(spread_mask(1, job.cpus.data(), job.threads(), cpus_of({0, 1, 2, 3, 4}), mask));
    EXPECT_TRUE(spread_mask(2, job.cpus.data(), job.threads(), cpus_of({0, 1, 2, 3, 4}), mask));
    EXPECT_FALSE(spread_mask(0, job.cpus.data(), job.threads(), cpus_of({0, 1, 2, 3, 4}), mask));
}

TEST(CpuSpread, ThreadsAloneOnTheirCpusStay) {
    const job_cpus job{0, 1, -1};
    cpu_set_t mask;
    EXPECT_FALSE(spread_mask(1, job.cpus.data(), job.threads(), cpus_of({0, 1, 2}), mask));
    EXPECT_FALSE(spread_mask(2, job.cpus.data(), job.threads(), cpus_of({0, 1, 2}), mask));
}

TEST(CpuSpread, NoMoveWithMoreThreadsThanCpus) {
    const job_cpus crowded{0, 0, 1};
    cpu_set_t mask;
    EXPECT_FALSE(spread_mask(1, crowded.cpus.data(), crowded.threads(), cpus_of({0, 1}), mask));
}

// A worker made while its caller may run on two CPUs, then the caller confined to one of them:
// the worker, wherever it starts, must run its later chunks on the other.
TEST(CpuSpread, ALiveWorkerLeavesItsCallersCpu) {
    cpu_set_t original;
    ASSERT_EQ(sched_getaffinity(0, sizeof original, &original), 0);
    std::vector<int> usable;
    for (int c = 0; c < CPU_SETSIZE && usable.size() < 2; ++c)
        if (CPU_ISSET(c, &original)) usable.push_back(c);
    if (usable.size() < 2) GTEST_SKIP() << "needs 2 CPUs";
    const cpu_set_t two = cpus_of({usable[0], usable[1]});
    ASSERT_EQ(sched_setaffinity(0, sizeof two, &two), 0);
    struct restore {
        cpu_set_t set;
        ~restore() { sched_setaffinity(0, sizeof set, &set); }
    } restore_affinity{original};

    // A fresh thread owns a fresh pool, so its worker starts with the two CPUs. On a loaded
    // machine the caller may run every chunk before the worker wakes: then try again, up to 50
    // times (a try takes about 40 ms of chunks).
    std::vector<int> worker_cpus;
    int caller_cpu = -1;
    auto one_try = [&] {
        worker_cpus.clear();
        std::thread caller([&] {
            frnn::parallel_chunks(2, 2, [](std::size_t, int) {});  // makes the worker
            const cpu_set_t one = cpus_of({usable[0]});
            sched_setaffinity(0, sizeof one, &one);
            caller_cpu = sched_getcpu();
            std::vector<int> seen(400, -1);
            frnn::parallel_chunks(seen.size(), 2, [&](std::size_t c, int worker) {
                if (worker == 1) seen[c] = sched_getcpu();
                const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(100);
                while (std::chrono::steady_clock::now() < end) {
                }
            });
            for (int s : seen)
                if (s >= 0) worker_cpus.push_back(s);
        });
        caller.join();
    };
    for (int attempt = 0; attempt < 50 && worker_cpus.size() < 4; ++attempt) {
        one_try();
        ASSERT_EQ(caller_cpu, usable[0]);
    }
    ASSERT_GE(worker_cpus.size(), 4u) << "in 50 tries the worker never ran 4 of 400 chunks";
    // A chunk already started when the worker found out may still run on the caller's CPU.
    for (std::size_t i = 2; i < worker_cpus.size(); ++i)
        EXPECT_NE(worker_cpus[i], caller_cpu) << "chunk " << i << " of the worker";
}

}  // namespace
