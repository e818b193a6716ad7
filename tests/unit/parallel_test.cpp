// frnn's thread pool (frnn/parallel.hpp): every chunk runs once, worker ids are distinct among
// running chunks, exceptions come back to the caller, nested and concurrent calls work, a forked
// child gets workers of its own, and the default thread count follows the environment.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/parallel.hpp"

namespace {

// Runs `chunks` chunks on `threads` threads and checks each ran once with a valid, unshared id.
void check_every_chunk_once(std::size_t chunks, int threads) {
    std::vector<std::atomic<int>> runs(chunks);
    std::vector<std::atomic<int>> busy(std::size_t(threads > 0 ? threads : frnn::default_thread_count()));
    std::atomic<int> bad_worker{0}, shared_worker{0};
    frnn::parallel_chunks(chunks, threads, [&](std::size_t c, int worker) {
        if (worker < 0 || std::size_t(worker) >= busy.size()) {
            ++bad_worker;
            return;
        }
        if (busy[std::size_t(worker)].exchange(1) != 0) ++shared_worker;
        runs[c].fetch_add(1);
        busy[std::size_t(worker)].store(0);
    });
    EXPECT_EQ(bad_worker.load(), 0);
    EXPECT_EQ(shared_worker.load(), 0);
    for (std::size_t c = 0; c < chunks; ++c) ASSERT_EQ(runs[c].load(), 1) << "chunk " << c << " of " << chunks;
}

TEST(ThreadPool, EveryChunkRunsOnceOnAValidWorker) {
    for (int threads : {0, 1, 2, 3, 8})
        for (std::size_t chunks : {0, 1, 2, 7, 64, 1000}) check_every_chunk_once(chunks, threads);
}

TEST(ThreadPool, ManyCallsInARow) {
    // Back-to-back calls meet workers still spinning from the last one or asleep; both must work.
    for (int round = 0; round < 2000; ++round) {
        std::atomic<std::size_t> sum{0};
        frnn::parallel_chunks(17, 3, [&](std::size_t c, int) { sum += c; });
        ASSERT_EQ(sum.load(), 17u * 16u / 2u);
        if (round % 500 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

TEST(ThreadPool, TheFirstExceptionReachesTheCallerAndThePoolStaysUsable) {
    // On one thread the chunks run in order and the throw ends the call: chunks 0 to 3 ran, once.
    std::vector<int> ran(100, 0);
    EXPECT_THROW(frnn::parallel_chunks(100, 1,
                                       [&](std::size_t c, int) {
                                           ++ran[c];
                                           if (c == 3) throw std::runtime_error("chunk 3");
                                       }),
                 std::runtime_error);
    std::vector<int> first_four(100, 0);
    std::fill_n(first_four.begin(), 4, 1);
    EXPECT_EQ(ran, first_four);

    // On 4 threads which chunks run is not fixed: a thread may start a chunk before it sees the
    // failure, or skip one it claimed before chunk 3 threw. What is fixed: chunk 3 ran once, no
    // chunk twice, and none still runs when its exception reaches the caller.
    std::vector<std::atomic<int>> started(100);
    std::atomic<int> running{0};
    struct leaving {
        std::atomic<int>& running;
        ~leaving() { --running; }
    };
    try {
        frnn::parallel_chunks(100, 4, [&](std::size_t c, int) {
            ++started[c];
            ++running;
            const leaving on_return_or_throw{running};
            if (c == 3) throw std::runtime_error("chunk 3");
        });
        ADD_FAILURE() << "the exception did not reach the caller";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "chunk 3");
        EXPECT_EQ(running.load(), 0) << "chunks still ran when the exception reached the caller";
    }
    EXPECT_EQ(started[3].load(), 1);
    for (std::size_t c = 0; c < started.size(); ++c) EXPECT_LE(started[c].load(), 1) << "chunk " << c;
    check_every_chunk_once(100, 4);
}

TEST(ThreadPool, ANestedCallRunsOnTheCallingThread) {
    std::atomic<int> elsewhere{0}, inner_chunks{0};
    frnn::parallel_chunks(8, 4, [&](std::size_t, int) {
        const auto me = std::this_thread::get_id();
        frnn::parallel_chunks(5, 4, [&](std::size_t, int worker) {
            if (std::this_thread::get_id() != me || worker != 0) ++elsewhere;
            ++inner_chunks;
        });
    });
    EXPECT_EQ(elsewhere.load(), 0);
    EXPECT_EQ(inner_chunks.load(), 8 * 5);
}

TEST(ThreadPool, CallersOnSeveralThreadsAtOnce) {
    std::vector<std::thread> callers;
    std::atomic<int> failures{0};
    for (int t = 0; t < 4; ++t)
        callers.emplace_back([&failures] {
            for (int round = 0; round < 200; ++round) {
                std::atomic<std::size_t> sum{0};
                frnn::parallel_chunks(50, 3, [&](std::size_t c, int) { sum += c + 1; });
                if (sum.load() != 50u * 51u / 2u) ++failures;
            }
        });
    for (auto& c : callers) c.join();
    EXPECT_EQ(failures.load(), 0);
}

TEST(ThreadPool, AForkedChildGetsWorkersOfItsOwn) {
    check_every_chunk_once(64, 2);  // the parent's pool exists before the fork
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        alarm(20);  // a hang fails the test instead of stalling it
        std::atomic<std::size_t> sum{0};
        frnn::parallel_chunks(64, 2, [&](std::size_t c, int) { sum += c; });
        _exit(sum.load() == 64u * 63u / 2u ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status)) << "the child did not exit normally (status " << status << ")";
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

// Sets an environment variable for one scope and restores it after.
class scoped_env {
public:
    scoped_env(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        if (value) setenv(name, value, 1);
        else unsetenv(name);
    }
    ~scoped_env() {
        if (old_) setenv(name_, old_->c_str(), 1);
        else unsetenv(name_);
    }
    scoped_env(const scoped_env&) = delete;
    scoped_env& operator=(const scoped_env&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

TEST(ThreadPool, DefaultThreadCountFollowsTheEnvironment) {
    const scoped_env frnn_unset("FRNN_NUM_THREADS", nullptr);
    {
        const scoped_env omp("OMP_NUM_THREADS", nullptr);
        EXPECT_GE(frnn::default_thread_count(), 1);
    }
    {
        const scoped_env omp("OMP_NUM_THREADS", "5,2");
        EXPECT_EQ(frnn::default_thread_count(), 5);
        const scoped_env frnn("FRNN_NUM_THREADS", "3");
        EXPECT_EQ(frnn::default_thread_count(), 3);
    }
    const scoped_env bad("FRNN_NUM_THREADS", "3x");
    try {
        static_cast<void>(frnn::default_thread_count());
        ADD_FAILURE() << "FRNN_NUM_THREADS=3x was accepted";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("FRNN_NUM_THREADS='3x'"), std::string::npos) << e.what();
    }
}

}  // namespace
