// The checkpoint file of `frnn sim` (checkpoint.bin): a magic tag, the scene's JSON text and
// origin, the run's metadata (command-line overrides, frames written, surge-front record), the
// next frame and front times, then the solver's state (solver::save). Written by runs every few
// frames and by frnn::sim::simulation::save_checkpoint; read by resume() and
// simulation::load_checkpoint.
#pragma once
#include <istream>
#include <string>
#include <utility>
#include <vector>

#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

namespace frnn::sim::detail {

/// Everything in a checkpoint before the solver's state.
struct checkpoint_header {
    std::string scene_json, origin;
    scene_overrides ov;
    std::vector<std::pair<double, std::string>> frames;  ///< (time, file) of the frames written
    double next_frame_time = 0;
    std::vector<std::pair<double, double>> front;  ///< (T, Z)
    double next_front_T = 0;
};

/// Writes the header and the solver's state to `path`, atomically.
void write_checkpoint(const std::string& path, const checkpoint_header& h, const solver& sol);
/// Reads the header from `in`, leaving it at the solver's state; `name` names the file in
/// messages. Throws frnn::error for anything else than a checkpoint.
checkpoint_header read_checkpoint_header(std::istream& in, const std::string& name);

}  // namespace frnn::sim::detail
