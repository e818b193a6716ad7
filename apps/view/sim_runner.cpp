#include "sim_runner.hpp"

#include <algorithm>
#include <chrono>

#include "frnn/error.hpp"
#include "frnn/parallel.hpp"
#include "median.hpp"

namespace frnn::view {
namespace {
using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point t0) { return std::chrono::duration<double>(clock_type::now() - t0).count(); }
}  // namespace

sim_runner::sim_runner(const sim::scene& s, int threads, double slow_step_ms)
    : sim_(s, threads), threads_(resolve_thread_count(threads)), slow_step_ms_(slow_step_ms), scene_(s) {
    sim_.snapshot(published_);
    fresh_ = true;
    thread_ = std::thread([this] { loop(); });
}

sim_runner::~sim_runner() {
    {
        std::lock_guard lock(mutex_);
        quit_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void sim_runner::send(std::function<void(sim::simulation&)> command) {
    {
        std::lock_guard lock(mutex_);
        commands_.push_back(std::move(command));
    }
    wake_.notify_all();
}

void sim_runner::set_playing(bool on) {
    playing_ = on;
    wake_.notify_all();
}

void sim_runner::step_once() { run_steps_async(1); }

void sim_runner::run_steps_async(int n) {
    {
        std::lock_guard lock(mutex_);
        pending_steps_ += n;
    }
    wake_.notify_all();
}

void sim_runner::reset() {
    send([](sim::simulation& s) { s.reset(); });
}

void sim_runner::set_scene(const sim::scene& next) {
    send([next](sim::simulation& s) { s.set_scene(next); });
}

void sim_runner::set_parameter(const sim::parameter& p, double value) {
    send([&p, value](sim::simulation& s) { s.set_parameter(p, value); });
}

void sim_runner::save_checkpoint(const std::string& path) {
    send([path](sim::simulation& s) { s.save_checkpoint(path); });
}

void sim_runner::load_checkpoint(const std::string& path) {
    send([this, path](sim::simulation& s) {
        s.load_checkpoint(path);
        just_loaded_ = true;  // told to the drawing thread by publish(), with the new scene
    });
}

bool sim_runner::take_loaded_scene(sim::scene& out) {
    std::lock_guard lock(mutex_);
    if (!loaded_) return false;
    out = scene_;
    loaded_ = false;
    return true;
}

void sim_runner::set_gravity(const sim::vec3& g) {
    send([g](sim::simulation& s) { s.set_gravity(g); });
}

void sim_runner::set_colliders(std::vector<sim::collider> list, std::optional<std::size_t> held) {
    send([this, list = std::move(list), held](sim::simulation& s) mutable {
        if (held && *held < list.size()) {
            list[*held] = hand_.follow(list[*held], s.time());
        } else {
            hand_.release();
        }
        s.set_colliders(std::move(list));
    });
}

void sim_runner::set_time_scale(double s) { time_scale_ = s; }

void sim_runner::run_steps(int n) {
    run_steps_async(n);
    wait_idle();
}

void sim_runner::wait_idle() {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return quit_ || (commands_.empty() && pending_steps_ == 0 && !busy_); });
}

bool sim_runner::take_snapshot(sim::particle_snapshot& out) {
    std::lock_guard lock(mutex_);
    if (!fresh_) return false;
    std::swap(out, published_);
    fresh_ = false;
    return true;
}

sim::scene sim_runner::scene_copy() const {
    std::lock_guard lock(mutex_);
    return scene_;
}

std::string sim_runner::last_error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

double sim_runner::mean_step_ms() const {
    std::lock_guard lock(mutex_);
    return timed_steps_ ? 1e3 * step_seconds_ / double(timed_steps_) : 0;
}

double sim_runner::mean_copy_ms() const {
    std::lock_guard lock(mutex_);
    return copies_ ? 1e3 * copy_seconds_ / double(copies_) : 0;
}

double sim_runner::median_step_ms() const {
    std::lock_guard lock(mutex_);
    return median(step_ms_);
}

sim_runner::stage_times sim_runner::recent_stage_ms() const {
    std::lock_guard lock(mutex_);
    return stage_ms_;
}

void sim_runner::capture_profile(int steps, const std::string& path) {
    send([this, steps, path](sim::simulation& s) {
        s.set_profiler(sim::profiler(true, threads_));
        capture_left_ = std::max(steps, 1);
        capture_path_ = path;
        std::lock_guard lock(mutex_);
        capture_status_ = "capturing " + std::to_string(capture_left_) + " steps";
    });
}

std::string sim_runner::capture_status() const {
    std::lock_guard lock(mutex_);
    return capture_status_;
}

void sim_runner::after_step(const stage_times& before) {
    const sim::profiler& prof = sim_.timings();
    std::string status;
    if (capture_left_ > 0 && --capture_left_ == 0) {
        // A reset or a new scene replaced the tracing profiler by a plain one.
        if (!prof.tracing()) {
            status = "profile capture interrupted by a reset";
        } else {
            prof.write_trace(capture_path_);  // throws frnn::error when it cannot
            status = "profile written to " + capture_path_;
        }
        sim_.set_profiler(sim::profiler());
    }
    std::lock_guard lock(mutex_);
    const bool first = timed_steps_ == 1;
    for (std::size_t k = 0; k < stage_ms_.size(); ++k) {
        const double ms = 1e3 * (prof.total_seconds(sim::stage(k)) - before[k]);
        stage_ms_[k] = first ? ms : 0.95 * stage_ms_[k] + 0.05 * ms;
    }
    if (!status.empty()) capture_status_ = status;
}

void sim_runner::publish() {
    const auto t0 = clock_type::now();
    sim_.snapshot(back_);
    const double dt = seconds_since(t0);
    std::lock_guard lock(mutex_);
    std::swap(back_, published_);
    fresh_ = true;
    copy_seconds_ += dt;
    ++copies_;
    scene_ = sim_.current_scene();
    loaded_ = loaded_ || just_loaded_;
    just_loaded_ = false;
}

void sim_runner::loop() {
    // Real-time pacing: simulated time may run ahead of wall time * scale by nothing.
    auto anchor_wall = clock_type::now();
    double anchor_sim = sim_.time();
    bool was_free_running = false;
    for (;;) {
        std::vector<std::function<void(sim::simulation&)>> commands;
        bool take_step = false;
        {
            std::unique_lock lock(mutex_);
            const auto free_running = [&] { return playing_.load(); };
            wake_.wait(lock, [&] { return quit_ || !commands_.empty() || pending_steps_ > 0 || free_running(); });
            if (quit_) return;
            commands.swap(commands_);
            if (pending_steps_ > 0) {
                --pending_steps_;
                take_step = true;
            }
            busy_ = true;
        }
        std::string failure;
        for (auto& c : commands) {
            try {
                c(sim_);
            } catch (const std::exception& e) {
                failure = e.what();
            }
        }
        if (!commands.empty()) publish();  // a reset or a new scene shows even while paused
        const bool free_running = playing_ && !take_step;
        if (free_running && !was_free_running) anchor_wall = clock_type::now(), anchor_sim = sim_.time();
        was_free_running = free_running;
        if (!commands.empty()) anchor_wall = clock_type::now(), anchor_sim = sim_.time();
        bool stepped = false;
        if (take_step || free_running) {
            const double scale = time_scale_;
            const double ahead = free_running && scale > 0 ? (sim_.time() - anchor_sim) / scale - seconds_since(anchor_wall) : 0;
            if (ahead > 0) {
                // Ahead of real time: wait, but wake for commands.
                std::unique_lock lock(mutex_);
                if (!failure.empty()) error_ = failure;
                busy_ = false;
                done_.notify_all();
                wake_.wait_for(lock, std::chrono::duration<double>(std::min(ahead, 0.05)),
                               [&] { return quit_ || !commands_.empty() || pending_steps_ > 0; });
                continue;
            }
            in_step_ = true;
            ++started_;
            stage_times before{};
            for (std::size_t k = 0; k < before.size(); ++k) before[k] = sim_.timings().total_seconds(sim::stage(k));
            const auto t0 = clock_type::now();
            if (slow_step_ms_ > 0) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(slow_step_ms_));
            try {
                sim_.step();
                stepped = true;
            } catch (const std::exception& e) {
                failure = e.what();
                playing_ = false;
            }
            const double dt = seconds_since(t0);
            in_step_ = false;
            {
                std::lock_guard lock(mutex_);
                step_seconds_ += dt;
                ++timed_steps_;
                step_ms_.push_back(1e3 * dt);
            }
            if (stepped) {
                try {
                    after_step(before);
                } catch (const std::exception& e) {
                    failure = e.what();
                }
            }
        }
        if (stepped) publish();
        std::lock_guard lock(mutex_);
        if (!failure.empty()) {
            error_ = failure;
            pending_steps_ = 0;
        } else if (!commands.empty()) {
            error_.clear();  // a reset or new scene starts clean; a step's error stays shown
        }
        busy_ = false;
        done_.notify_all();
    }
}

}  // namespace frnn::view
