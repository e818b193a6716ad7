// Per-stage timing of the solvers: mean wall milliseconds per step for each stage (the table
// printed at the end of a run), the process CPU time of each stage (a measure that a machine
// shared with other jobs inflates less than wall time) and, when tracing, one span per stage per thread per step written as a
// Chrome trace (chrome://tracing, Perfetto).
//
// Thread safety: add() from the calling thread only; span() from inside parallel regions, each
// thread writing only its own buffer (indexed by its OpenMP thread number).
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace frnn::sim {

enum class stage { grid, neighbors, viscosity, springs, relaxation, density, forces, collisions, integration, output, count };
const char* to_string(stage s);

class profiler {
public:
    explicit profiler(bool trace = false, int max_threads = 1);
    /// Seconds since the profiler was made.
    double now() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    void add(stage s, double seconds) { total_[std::size_t(s)] += seconds; }
    /// CPU seconds of the whole process (all threads, spinning included).
    static double cpu_now();
    void add_cpu(stage s, double seconds) { cpu_[std::size_t(s)] += seconds; }
    double mean_cpu_ms(stage s) const { return steps_ ? 1e3 * cpu_[std::size_t(s)] / double(steps_) : 0; }
    void set_step(std::uint64_t step) { step_ = step; }
    void end_step() { ++steps_; }
    std::uint64_t steps() const { return steps_; }
    bool tracing() const { return trace_; }
    /// Records that `thread` worked on stage s from t0 to t1 (seconds, from now()). Spans of the
    /// same stage, thread and step are merged.
    void span(stage s, int thread, double t0, double t1);
    double total_seconds(stage s) const { return total_[std::size_t(s)]; }
    double mean_ms(stage s) const { return steps_ ? 1e3 * total_[std::size_t(s)] / double(steps_) : 0; }
    /// Mean ms per step of all stages but output.
    double mean_step_ms() const;
    /// The table of mean ms per stage (stages never timed are left out).
    std::string table() const;
    /// Writes the Chrome trace JSON (atomically).
    void write_trace(const std::string& path) const;

private:
    struct event {
        stage s;
        std::uint64_t step;
        double t0, t1;
    };
    bool trace_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::array<double, std::size_t(stage::count)> total_{}, cpu_{};
    std::uint64_t steps_ = 0, step_ = 0;
    std::vector<std::vector<event>> events_;  // per thread
};

/// Adds the wall time of a scope to a stage.
class stage_timer {
public:
    stage_timer(profiler& p, stage s) : p_(p), s_(s), t0_(p.now()), c0_(profiler::cpu_now()) {}
    ~stage_timer() {
        p_.add(s_, p_.now() - t0_);
        p_.add_cpu(s_, profiler::cpu_now() - c0_);
    }
    stage_timer(const stage_timer&) = delete;
    stage_timer& operator=(const stage_timer&) = delete;

private:
    profiler& p_;
    stage s_;
    double t0_, c0_;
};

}  // namespace frnn::sim
