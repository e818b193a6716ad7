// Stage timing table and Chrome trace output.
#include "frnn/sim/profiler.hpp"

#include <time.h>

#include <cstdio>
#include <sstream>

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

std::string profiler::table() const {
    std::ostringstream o;
    char line[160];
    std::snprintf(line, sizeof line, "%-24s %12s %8s %14s\n", "stage", "ms/step", "share", "cpu ms/step");
    o << line;
    double all = 0;
    for (double t : total_) all += t;
    for (std::size_t i = 0; i < total_.size(); ++i) {
        if (total_[i] == 0) continue;
        std::snprintf(line, sizeof line, "%-24s %12.3f %7.1f%% %14.3f\n", to_string(stage(i)), mean_ms(stage(i)),
                      all > 0 ? 100 * total_[i] / all : 0.0, mean_cpu_ms(stage(i)));
        o << line;
    }
    double cpu_all = 0, cpu_out = cpu_[std::size_t(stage::output)];
    for (double t : cpu_) cpu_all += t;
    const double per = steps_ ? 1e3 / double(steps_) : 0;
    std::snprintf(line, sizeof line, "%-24s %12.3f %8s %14.3f\n%-24s %12.3f %8s %14.3f\n", "step (without output)", mean_step_ms(), "",
                  (cpu_all - cpu_out) * per, "total", all * per, "", cpu_all * per);
    o << line;
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
    write_file_atomic(path, o.str());
}

}  // namespace frnn::sim
