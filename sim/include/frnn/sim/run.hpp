// Running a scene to completion: the time loop, output frames (.vtp, .pvd, optional PNG and
// MP4), the surge-front record, atomic checkpoints every few frames and resuming from them,
// progress on stderr, the per-stage timing table and summary.json, optionally under a load.
//
// Output directory layout: frames/frame_NNNNN.vtp, particles.pvd, summary.json,
// checkpoint.bin, [front.csv], [png/frame_NNNNN.png], [particles.mp4].
// Thread safety: one run per process directory; run() uses `threads` threads of frnn's pool.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "frnn/sim/ranks.hpp"
#include "frnn/sim/scene.hpp"

namespace frnn::sim {

/// An outside load switched on and off during a run, to compare the steps' speed with and
/// without it (`frnn sim --contend`). Steps go in blocks of `block_steps`: the first block warms
/// up (quiet, not counted), then quiet and busy blocks alternate; a last, incomplete block is not
/// counted. The table and summary.json give per stage the medians over the quiet and over the
/// busy blocks, or say that the run was too short for profiler::min_blocks of each kind.
struct load_hook {
    std::function<void(bool busy)> set;  ///< switches the load on (true) or off; empty: no load
    std::uint64_t block_steps = 10;      ///< > 0
    std::string label;                   ///< what the load is, for the table and summary.json
};

struct run_options {
    std::string out_dir;         ///< empty: a new folder named after the scene and the time
    int threads = 0;             ///< 0: all hardware threads
    std::string trace_path;      ///< Chrome trace JSON, written at the end
    bool png = false, video = false;
    bool write_frames = true;    ///< .vtp frames and particles.pvd
    bool progress = true;        ///< progress on stderr
    bool print_table = true;     ///< the per-stage table on stdout at the end
    std::uint64_t stop_after = 0;  ///< stop (as if interrupted) after this many steps of this run
    load_hook load;              ///< steps under an outside load in blocks; none by default
    /// The ranks this run spans (frnn/sim/ranks.hpp); none, or one rank: one process. Across
    /// several, every rank calls run() alike: rank 0 alone writes the output folder and prints.
    std::shared_ptr<rank_comm> ranks;
    balance_options balance;  ///< across ranks: when the cut follows the fluid
};

struct run_result {
    std::string out_dir;
    std::uint64_t steps = 0;      ///< total steps of the simulation
    std::size_t particles = 0;
    std::size_t wall_particles = 0;  ///< solver::wall_particle_count
    std::size_t frames = 0;
    double sim_time = 0, wall_seconds = 0, step_ms = 0;
    std::vector<std::pair<std::string, double>> stage_ms;  ///< mean ms per step by stage
    std::vector<std::pair<double, double>> front;           ///< (T, Z) when the scene records it
    /// Per series of martin_moyce() (same order): the front's error (front_error), when the
    /// scene records the front and the run covers the T range; else empty.
    std::vector<double> front_errors;
    bool finished = false;
    /// Under a load (run_options::load): the complete blocks of each kind and, when there are at
    /// least profiler::min_blocks of each, the medians of their ms per step without output.
    std::size_t quiet_blocks = 0, contended_blocks = 0;
    double quiet_step_ms = 0, contended_step_ms = 0;
};

/// Runs a scene given as JSON text (origin names it in messages) with command-line overrides.
run_result run(const std::string& scene_json, const std::string& origin, const scene_overrides& overrides,
               const run_options& options);
/// Continues the run in `dir` from its last checkpoint, writing into the same directory.
run_result resume(const std::string& dir, const run_options& options);

}  // namespace frnn::sim
