// The load generator of --contend: threads and children do busy work only while busy (their
// iteration count, and a child's CPU time in /proc, grow while busy and stand still while
// quiet), children are stopped while quiet, and none is left, not even a zombie, after the
// object is gone: destroyed quiet, busy, by an exception, or with its parent process. No
// timing is asserted: "grows" waits as long as it takes, "stands still" compares counts.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "frnn/bench/contention.hpp"
#include "frnn/error.hpp"

using frnn::bench::contention;
using namespace std::chrono_literals;

namespace {

// Waits until `ok` holds; false after a minute (a machine so loaded that a busy thread never
// ran in a minute is broken, not slow).
bool eventually(const std::function<bool()>& ok) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    while (!ok()) {
        if (std::chrono::steady_clock::now() > deadline) return false;
        std::this_thread::sleep_for(1ms);
    }
    return true;
}

struct proc_stat {
    char state = '?';        // R running, S sleeping, T stopped, Z zombie; '?' no such process
    long long cpu_ticks = 0;  // utime + stime
};

proc_stat read_stat(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    proc_stat s;
    const auto close = text.rfind(')');
    if (close == std::string::npos) return s;
    std::istringstream fields(text.substr(close + 2));
    std::string skip;
    fields >> s.state;
    for (int k = 0; k < 10; ++k) fields >> skip;  // ppid .. cmajflt
    long long utime = 0, stime = 0;
    fields >> utime >> stime;
    s.cpu_ticks = utime + stime;
    return s;
}

bool gone(pid_t pid) { return ::kill(pid, 0) == -1 && errno == ESRCH; }

// Busy, quiet, busy, quiet: the count grows in each busy spell and is frozen in each quiet one.
void check_switching(contention& load) {
    std::this_thread::sleep_for(20ms);
    EXPECT_EQ(load.iterations(), 0u) << "worked before the first busy()";
    for (int round = 0; round < 2; ++round) {
        const std::uint64_t before = load.iterations();
        load.busy();
        EXPECT_TRUE(load.is_busy());
        EXPECT_TRUE(eventually([&] { return load.iterations() > before; })) << "no work while busy";
        load.quiet();
        EXPECT_FALSE(load.is_busy());
        const std::uint64_t frozen = load.iterations();
        std::this_thread::sleep_for(30ms);
        EXPECT_EQ(load.iterations(), frozen) << "worked while quiet";
    }
}

TEST(Contention, ThreadsWorkOnlyWhileBusy) {
    contention load(2, contention::mode::threads);
    EXPECT_TRUE(load.children().empty());
    check_switching(load);
}

TEST(Contention, ChildrenWorkOnlyWhileBusy) {
    contention load(2, contention::mode::processes);
    ASSERT_EQ(load.children().size(), 2u);
    for (pid_t pid : load.children()) EXPECT_EQ(read_stat(pid).state, 'T') << "a new child is stopped";
    check_switching(load);

    // The kernel's view: CPU time grows while busy, and a quiet child is stopped and uses none.
    load.busy();
    for (pid_t pid : load.children()) {
        const long long before = read_stat(pid).cpu_ticks;
        EXPECT_TRUE(eventually([&] { return read_stat(pid).cpu_ticks > before; })) << pid;
    }
    load.quiet();
    for (pid_t pid : load.children()) {
        const proc_stat quiet = read_stat(pid);
        EXPECT_EQ(quiet.state, 'T') << pid;
        std::this_thread::sleep_for(30ms);
        EXPECT_EQ(read_stat(pid).cpu_ticks, quiet.cpu_ticks) << pid;
    }
}

TEST(Contention, SwitchingTwiceIsHarmless) {
    for (auto mode : {contention::mode::threads, contention::mode::processes}) {
        contention load(1, mode);
        load.quiet();
        load.busy();
        load.busy();
        EXPECT_TRUE(load.is_busy());
        load.quiet();
        load.quiet();
        EXPECT_FALSE(load.is_busy());
    }
}

TEST(Contention, NoChildIsLeftBehind) {
    std::vector<pid_t> pids;
    {
        contention quiet(2, contention::mode::processes);
        pids = quiet.children();
    }
    {
        contention busy(2, contention::mode::processes);
        busy.busy();
        pids.insert(pids.end(), busy.children().begin(), busy.children().end());
    }
    try {
        contention load(1, contention::mode::processes);
        pids.push_back(load.children().front());
        load.busy();
        throw std::runtime_error("a failure while busy");
    } catch (const std::runtime_error&) {
    }
    ASSERT_EQ(pids.size(), 5u);
    for (pid_t pid : pids) {
        EXPECT_TRUE(gone(pid)) << pid << " is still there (a zombie is not reaped)";
        EXPECT_EQ(::waitpid(pid, nullptr, WNOHANG), -1) << pid;  // reaped: no longer our child
    }
}

TEST(Contention, ThreadsEndWhenDestroyedBusyOrQuiet) {
    contention quiet(3, contention::mode::threads);
    contention busy(3, contention::mode::threads);
    busy.busy();
    // Both destructors must return (join); a hang here fails by the test timeout.
}

TEST(Contention, ChildDiesWithItsParent) {
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const pid_t parent = ::fork();
    ASSERT_GE(parent, 0);
    if (parent == 0) {  // a parent that dies without running the destructor
        ::close(fds[0]);
        contention* load = new contention(1, contention::mode::processes);
        load->busy();
        const pid_t child = load->children().front();
        const bool sent = ::write(fds[1], &child, sizeof child) == sizeof child;
        ::_exit(sent ? 0 : 1);
    }
    ::close(fds[1]);
    pid_t child = 0;
    const bool received = ::read(fds[0], &child, sizeof child) == sizeof child;
    ::close(fds[0]);
    int status = 0;
    ASSERT_EQ(::waitpid(parent, &status, 0), parent);
    ASSERT_TRUE(received);
    ASSERT_GT(child, 0);
    // Orphaned, it is killed and reaped by whoever adopts it; a zombie counts as dead.
    EXPECT_TRUE(eventually([&] { return gone(child) || read_stat(child).state == 'Z'; }));
}

TEST(Contention, KOutOfRangeIsAnError) {
    for (int k : {0, -1, 65})
        for (auto mode : {contention::mode::threads, contention::mode::processes})
            EXPECT_THROW(contention(k, mode), frnn::error) << k;
}

TEST(Contention, Describes) {
    EXPECT_EQ(contention(1, contention::mode::threads).describe(), "1 busy thread in this process");
    EXPECT_EQ(contention(2, contention::mode::threads).describe(), "2 busy threads in this process");
    EXPECT_EQ(contention(1, contention::mode::processes).describe(), "1 busy child process");
    EXPECT_EQ(contention(3, contention::mode::processes).describe(), "3 busy child processes");
    const std::string autogroup = frnn::bench::autogroup_scheduling();
    EXPECT_TRUE(autogroup == "on" || autogroup == "off" || autogroup == "unknown") << autogroup;
}

}  // namespace
