// Wall-clock laps in milliseconds, for the phase times frnn reports (the tool's summaries, the
// MPI layer's statistics). Thread safety: one object per thread.
#pragma once
#include <chrono>

namespace frnn::detail {

class stopwatch {
public:
    /// Milliseconds since the last lap (or construction).
    double lap_ms() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
        return ms;
    }

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace frnn::detail
