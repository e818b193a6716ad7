// Per-stage timing of the solvers: mean wall milliseconds per step for each stage (the table
// printed at the end of a run), the process CPU time of each stage (a measure that a machine
// shared with other jobs inflates less than wall time), under a load switched in blocks of
// steps the medians over quiet and over contended blocks and, when tracing, one span per stage
// per thread per step written as a Chrome trace (chrome://tracing, Perfetto).
//
// Thread safety: add() from the calling thread only; span() from inside parallel regions, each
// thread writing only its own buffer (indexed by its worker number in frnn::parallel_chunks).
#pragma once
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace frnn::sim {

enum class stage { grid, neighbors, viscosity, springs, relaxation, density, forces, collisions, integration, exchange, output, count };
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

    /// Under a load switched in blocks of steps: the steps from now on form a block, quiet or
    /// busy (the load ran); a block started before and not ended is dropped.
    void start_block(bool busy);
    /// Ends the current block (if it has steps) and keeps its ms per step of each stage.
    void end_block();
    /// The number of blocks kept of one kind.
    std::size_t blocks(bool busy) const;
    /// Fewest blocks of each kind behind a comparison of quiet and contended medians.
    static constexpr std::size_t min_blocks = 5;
    bool enough_blocks() const { return std::min(blocks(false), blocks(true)) >= min_blocks; }
    /// Median over the kept blocks of one kind of a stage's ms per step; 0 without blocks.
    double block_median_ms(bool busy, stage s) const;
    /// The same for the whole step without output.
    double block_median_step_ms(bool busy) const;

    /// The table of mean ms per stage (stages never timed are left out). With `load_columns`
    /// also the block medians, quiet and contended, and their ratio; "-" for output (frames
    /// fall unevenly into blocks) and everywhere when !enough_blocks().
    std::string table(bool load_columns = false) const;
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

    static constexpr std::size_t step_slot = std::size_t(stage::count);  // the step without output
    struct block {
        bool busy;
        std::array<double, step_slot + 1> ms_per_step;  // by stage, then the step without output
    };
    double block_median(bool busy, std::size_t slot) const;
    std::vector<block> blocks_;
    bool in_block_ = false, block_busy_ = false;
    std::array<double, std::size_t(stage::count)> block_start_{};  // total_ when the block began
    std::uint64_t block_start_steps_ = 0;
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
