// The simulation on a thread of its own. The drawing thread sends commands (play, pause, step,
// reset, parameters, a new scene); the simulation thread applies them between steps, so the
// simulation is only ever touched by its own thread. After each step it copies the particles
// into a snapshot and publishes it by a swap under a mutex (triple buffering: one being
// written, one published, one being drawn), so drawing never waits for a step and always
// reads the fields of one step.
//
// Decoupled (default): while playing, steps run back to back, paced by the time scale.
// Lockstep (scripts, tests): the drawing thread asks for exactly S steps per frame and waits.
#pragma once
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "collider_hand.hpp"
#include "frnn/sim/simulation.hpp"

namespace frnn::view {

class sim_runner {
public:
    /// Seeds the scene on the calling thread (so a bad scene throws here), then starts the
    /// thread. slow_step_ms > 0 sleeps that long before each step (a test of decoupling).
    sim_runner(const sim::scene& s, int threads, double slow_step_ms);
    ~sim_runner();
    sim_runner(const sim_runner&) = delete;
    sim_runner& operator=(const sim_runner&) = delete;

    void set_playing(bool on);
    bool playing() const { return playing_; }
    /// One step (also while paused).
    void step_once();
    void reset();
    /// A new scene, seeded on the simulation thread; a scene that fails leaves the old one and
    /// its message in last_error().
    void set_scene(const sim::scene& s);
    void set_parameter(const sim::parameter& p, double value);
    /// Saves the state as a checkpoint (frnn sim's format) / replaces scene and state by one.
    void save_checkpoint(const std::string& path);
    void load_checkpoint(const std::string& path);
    /// After a checkpoint was loaded: its scene, once (true then).
    bool take_loaded_scene(sim::scene& out);
    void set_gravity(const sim::vec3& g);
    /// Colliders edited by hand, from the next step on (the particles stay): with `held`, the
    /// collider of that index is being dragged, and moves on with the velocity of its last
    /// displacement over the simulated time in between (collider_hand.hpp); without, every
    /// collider has only its scripted motion.
    void set_colliders(std::vector<sim::collider> list, std::optional<std::size_t> held = std::nullopt);
    /// Simulated seconds per wall second while playing decoupled; 0: as fast as possible.
    void set_time_scale(double s);
    double time_scale() const { return time_scale_; }

    /// Lockstep: runs n steps now and returns when they and their snapshot are done.
    void run_steps(int n);
    /// Waits until every command sent so far has been applied and published.
    void wait_idle();

    /// Swaps the newest snapshot into `out` when there is one not yet taken; returns true then.
    bool take_snapshot(sim::particle_snapshot& out);
    /// The scene as the simulation thread has it now (parameters included).
    sim::scene scene_copy() const;
    /// The last error of a step or a command ("" if none); a failing step pauses the run.
    std::string last_error() const;

    /// True while the simulation thread is inside a step; step_index() counts started steps.
    bool in_step() const { return in_step_; }
    std::uint64_t started_steps() const { return started_; }
    /// Mean wall milliseconds per step and per snapshot copy since the start.
    double mean_step_ms() const;
    double mean_copy_ms() const;
    /// The median wall milliseconds of the steps since the start (0 before any).
    double median_step_ms() const;

    /// Milliseconds per step of each solver stage (sim::stage), averaged over about the last
    /// 20 steps (exponentially), for the panel's live timing bar; zeros before the first step.
    using stage_times = std::array<double, std::size_t(sim::stage::count)>;
    stage_times recent_stage_ms() const;
    /// Writes a Chrome trace (sim::profiler::write_trace) of the next `steps` steps to `path`.
    /// A reset or new scene during them interrupts the capture; capture_status() tells how it
    /// went ("" before any).
    void capture_profile(int steps, const std::string& path);
    std::string capture_status() const;

private:
    void run_steps_async(int n);
    void send(std::function<void(sim::simulation&)> command);
    void loop();
    void publish();
    /// After a step: the stage times and the capture under way (simulation thread).
    void after_step(const stage_times& before);

    sim::simulation sim_;
    int threads_;
    double slow_step_ms_;
    mutable std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::vector<std::function<void(sim::simulation&)>> commands_;
    int pending_steps_ = 0;
    bool quit_ = false, busy_ = false, fresh_ = false, loaded_ = false;
    bool just_loaded_ = false;  // simulation thread only
    std::atomic<bool> playing_{false}, in_step_{false};
    std::atomic<double> time_scale_{1.0};
    std::atomic<std::uint64_t> started_{0};
    sim::particle_snapshot back_, published_;
    sim::scene scene_;  // copy for the drawing thread, under mutex_
    std::string error_;
    double step_seconds_ = 0, copy_seconds_ = 0;
    std::uint64_t timed_steps_ = 0, copies_ = 0;
    std::vector<double> step_ms_;  // every step's, for the median; under mutex_
    stage_times stage_ms_{};          // under mutex_
    std::string capture_status_;      // under mutex_
    int capture_left_ = 0;            // simulation thread only
    std::string capture_path_;        // simulation thread only
    collider_hand hand_;              // simulation thread only
    std::thread thread_;
};

}  // namespace frnn::view
