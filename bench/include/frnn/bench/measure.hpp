// Measuring: a stopwatch, the median of repeated runs after a warm-up, the process's peak
// resident memory, and a description of the machine. Not thread-safe (peak-RSS resets touch
// the whole process); call from the thread that drives the benchmark.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

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
/// (warm-up included) found different numbers of pairs.
struct measurement {
    double median_ms = 0;
    std::optional<std::uint64_t> pairs;
    bool pairs_agree = true;
};

double median(std::vector<double> values);

/// Runs `once` (which returns a sample, timing only the work it measures) 1 + repeat times.
template <class F>
measurement measure(int repeat, F&& once) {
    measurement m;
    const sample warm = once();
    m.pairs = warm.pairs;
    std::vector<double> times;
    for (int r = 0; r < std::max(repeat, 1); ++r) {
        const sample s = once();
        times.push_back(s.ms);
        if (s.pairs != m.pairs) m.pairs_agree = false;
    }
    m.median_ms = median(std::move(times));
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
