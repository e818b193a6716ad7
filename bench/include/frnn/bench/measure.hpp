// Measuring: a stopwatch, the median of repeated runs after a warm-up (optionally each run
// paired with one under load), the process's peak resident memory, and a description of the
// machine. Not thread-safe (peak-RSS resets touch the whole process); call from the thread that
// drives the benchmark.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "frnn/bench/contention.hpp"

namespace frnn::bench {

class stopwatch {
public:
    void start() { begin_ = std::chrono::steady_clock::now(); }
    /// Milliseconds since start().
    double stop() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin_)
            .count();
    }

private:
    std::chrono::steady_clock::time_point begin_;
};

/// One run of a phase: its time and, for phases that search, the pairs it found.
struct sample {
    double ms = 0;
    std::optional<std::uint64_t> pairs;
};

/// Median time of `repeat` runs after one warm-up run; `pairs_agree` is false when the runs
/// (warm-up and contended runs included) found different numbers of pairs. Under a load,
/// `median_ms` is still that of the quiet runs.
struct measurement {
    double median_ms = 0;
    std::optional<std::uint64_t> pairs;
    bool pairs_agree = true;
    std::optional<double> contended_ms;  ///< median of the runs under load; none without load
    int load_pairs = 0;                  ///< quiet/contended pairs of runs; 0 without load
};

double median(std::vector<double> values);

/// Under load: the fewest pairs of runs, and the pause after busy() before a contended run so
/// that the load is running (scheduled and spread over the cores) when the timing starts.
inline constexpr int min_load_pairs = 5;
inline constexpr std::chrono::milliseconds load_settle{10};

/// Runs `once` (which returns a sample, timing only the work it measures) 1 + repeat times.
/// With a `load`: max(repeat, min_load_pairs) pairs after the warm-up, each a quiet run, then
/// the load on, load_settle, a contended run, and the load off; quiet and contended runs
/// alternate so that a drift of the machine (other jobs, clock speed) touches both alike.
template <class F>
measurement measure(int repeat, F&& once, contention* load = nullptr) {
    measurement m;
    const sample warm = once();
    m.pairs = warm.pairs;
    const auto timed = [&](std::vector<double>& times) {
        const sample s = once();
        times.push_back(s.ms);
        if (s.pairs != m.pairs) m.pairs_agree = false;
    };
    std::vector<double> quiet, contended;
    const int runs = load ? std::max(repeat, min_load_pairs) : std::max(repeat, 1);
    for (int r = 0; r < runs; ++r) {
        timed(quiet);
        if (!load) continue;
        load->busy();
        std::this_thread::sleep_for(load_settle);
        timed(contended);
        load->quiet();
    }
    m.median_ms = median(std::move(quiet));
    if (load) {
        m.contended_ms = median(std::move(contended));
        m.load_pairs = runs;
    }
    return m;
}

/// Returns freed heap memory to the system (glibc), then resets the process's peak RSS to its
/// current RSS (Linux /proc/self/clear_refs); false when the kernel refuses, in which case
/// peak_rss_bytes() is the peak since the process started.
bool reset_peak_rss();
/// Peak resident set size: VmHWM of /proc/self/status, else getrusage's ru_maxrss.
std::size_t peak_rss_bytes();

/// "model name" of /proc/cpuinfo, or "unknown CPU".
std::string cpu_model();
/// Compiler and build flavour, e.g. "g++ 12.2.0, optimised (NDEBUG)".
std::string build_description();

}  // namespace frnn::bench
