// The command line of frnn-view (and of `frnn view`, which passes it on).
#pragma once
#include <cstddef>
#include <optional>
#include <string>

#include "frnn/sim/scene.hpp"

namespace frnn::view {

struct view_options {
    std::string scene_file, scene_name;
    sim::scene_overrides overrides;  ///< --solver, --dim, --particles
    int threads = 0;
    std::string script_file, screenshot_file, state_file;
    long frames = 0;  ///< > 0: quit after this many frames
    int width = 1280, height = 720;
    double slow_step_ms = 0;  ///< test hook: every step sleeps this long first
    bool paused = false;      ///< start paused
    bool timing = false;      ///< finish each frame (glFinish) and print mean and median times at the end
};

}  // namespace frnn::view
