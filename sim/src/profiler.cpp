// Stage timing table and Chrome trace output.
#include "frnn/sim/profiler.hpp"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "frnn/io/atomic_file.hpp"
#include "frnn/sim/output.hpp"

namespace frnn::sim {

const char* to_string(stage s) {
    switch (s) {
        case stage::grid: return "grid build + reorder";
        case stage::neighbors: return "neighbor lists";
        case stage::viscosity: return "viscosity";
        case stage::springs: return "springs";
        case stage::relaxation: return "density relaxation";
        case stage::density: return "density";
        case stage::forces: return "forces";
        case stage::collisions: return "collisions";
        case stage::integration: return "integration";
        case stage::exchange: return "rank exchange";
        case stage::output: return "output";
        case stage::count: break;
    }
    return "?";
}

double profiler::cpu_now() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

profiler::profiler(bool trace, int max_threads) : trace_(trace), events_(std::size_t(std::max(1, max_threads))) {}

void profiler::span(stage s, int thread, double t0, double t1) {
    if (!trace_ || thread < 0 || std::size_t(thread) >= events_.size()) return;
    auto& ev = events_[std::size_t(thread)];
    if (!ev.empty() && ev.back().s == s && ev.back().step == step_) {
        ev.back().t1 = t1;
        return;
    }
    if (ev.size() < 4'000'000) ev.push_back({s, step_, t0, t1});
}

double profiler::mean_step_ms() const {
    double sum = 0;
    for (std::size_t i = 0; i < total_.size(); ++i)
        if (stage(i) != stage::output) sum += total_[i];
    return steps_ ? 1e3 * sum / double(steps_) : 0;
}

void profiler::start_block(bool busy) {
    in_block_ = true;
    block_busy_ = busy;
    block_start_ = total_;
    block_start_steps_ = steps_;
}

void profiler::end_block() {
    if (!in_block_ || steps_ == block_start_steps_) return;
    in_block_ = false;
    block b{block_busy_, {}};
    const double per_step = 1e3 / double(steps_ - block_start_steps_);
    for (std::size_t i = 0; i < total_.size(); ++i) {
        b.ms_per_step[i] = (total_[i] - block_start_[i]) * per_step;
        if (stage(i) != stage::output) b.ms_per_step[step_slot] += b.ms_per_step[i];
    }
    blocks_.push_back(b);
}

std::size_t profiler::blocks(bool busy) const {
    return std::size_t(std::count_if(blocks_.begin(), blocks_.end(), [&](const block& b) { return b.busy == busy; }));
}

double profiler::block_median(bool busy, std::size_t slot) const {
    std::vector<double> v;
    for (const block& b : blocks_)
        if (b.busy == busy) v.push_back(b.ms_per_step[slot]);
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t mid = v.size() / 2;
    return v.size() % 2 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
}

double profiler::block_median_ms(bool busy, stage s) const { return block_median(busy, std::size_t(s)); }
double profiler::block_median_step_ms(bool busy) const { return block_median(busy, step_slot); }

std::string profiler::table(bool load_columns) const {
    std::ostringstream o;
    char line[200];
    // The quiet and contended medians of one slot (a stage or the step), or dashes for the
    // output stage and the total (frames fall unevenly into blocks), and for too few blocks.
    const auto load_cells = [&](std::size_t slot) {
        char cells[80];
        if (!load_columns) return std::string("\n");
        if (!enough_blocks() || slot == std::size_t(stage::output) || slot > step_slot) {
            std::snprintf(cells, sizeof cells, " %14s %18s %16s\n", "-", "-", "-");
            return std::string(cells);
        }
        const double q = block_median(false, slot), c = block_median(true, slot);
        if (q > 0)
            std::snprintf(cells, sizeof cells, " %14.3f %18.3f %16.2f\n", q, c, c / q);
        else
            std::snprintf(cells, sizeof cells, " %14.3f %18.3f %16s\n", q, c, "-");
        return std::string(cells);
    };
    std::snprintf(line, sizeof line, "%-24s %12s %8s %14s", "stage", "ms/step", "share", "cpu ms/step");
    o << line;
    if (load_columns) {
        std::snprintf(line, sizeof line, " %14s %18s %16s", "quiet ms/step", "contended ms/step", "contended/quiet");
        o << line;
    }
    o << "\n";
    double all = 0;
    for (double t : total_) all += t;
    for (std::size_t i = 0; i < total_.size(); ++i) {
        if (total_[i] == 0) continue;
        std::snprintf(line, sizeof line, "%-24s %12.3f %7.1f%% %14.3f", to_string(stage(i)), mean_ms(stage(i)),
                      all > 0 ? 100 * total_[i] / all : 0.0, mean_cpu_ms(stage(i)));
        o << line << load_cells(i);
    }
    double cpu_all = 0, cpu_out = cpu_[std::size_t(stage::output)];
    for (double t : cpu_) cpu_all += t;
    const double per = steps_ ? 1e3 / double(steps_) : 0;
    std::snprintf(line, sizeof line, "%-24s %12.3f %8s %14.3f", "step (without output)", mean_step_ms(), "",
                  (cpu_all - cpu_out) * per);
    o << line << load_cells(step_slot);
    std::snprintf(line, sizeof line, "%-24s %12.3f %8s %14.3f", "total", all * per, "", cpu_all * per);
    o << line << load_cells(step_slot + 1);
    return o.str();
}

void profiler::write_trace(const std::string& path) const {
    std::ostringstream o;
    o << "{\"displayTimeUnit\":\"ms\",\"traceEvents\":[\n";
    bool first = true;
    for (std::size_t t = 0; t < events_.size(); ++t) {
        o << (first ? "" : ",\n") << R"({"name":"thread_name","ph":"M","pid":1,"tid":)" << t
          << R"(,"args":{"name":"worker )" << t << "\"}}";
        first = false;
        for (const auto& e : events_[t]) {
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          ",\n{\"name\":\"%s\",\"cat\":\"sim\",\"ph\":\"X\",\"pid\":1,\"tid\":%zu,\"ts\":%.3f,"
                          "\"dur\":%.3f,\"args\":{\"step\":%llu}}",
                          to_string(e.s), t, e.t0 * 1e6, (e.t1 - e.t0) * 1e6, (unsigned long long)e.step);
            o << buf;
        }
    }
    o << "\n]}\n";
    io::write_file_atomically(path, o.str());
}

}  // namespace frnn::sim
