// frnn-view: runs a particle-fluid scene live in a window with a control panel. Exit codes:
// 0 success, 1 bad input or failure (one line on stderr), 2 usage error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "launcher.hpp"  // apps/frnn: how the tool tells a launcher
#include "frnn/error.hpp"
#include "frnn/sim/scene.hpp"
#include "viewer.hpp"

namespace {

frnn::sim::scene load(const frnn::view::view_options& o) {
    if (!o.scene_file.empty() && !o.scene_name.empty()) throw frnn::error("give either a scene file or --scene, not both");
    frnn::sim::scene s = o.scene_file.empty() ? frnn::sim::builtin_scene(o.scene_name.empty() ? "dam-break" : o.scene_name)
                                              : frnn::sim::load_scene(o.scene_file);
    frnn::sim::apply(s, o.overrides);
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    // One window per rank would be one independent simulation each: refused, from rank 0 only
    // (the others end quietly, so that the launcher cannot end rank 0 before its message is out).
    if (frnn::app::launcher_ranks() > 1) {
        if (frnn::app::launcher_rank() != 0) return 0;
        std::fprintf(stderr, "frnn-view: the viewer runs in one process, but an MPI launcher started %ld ranks: run it "
                             "without mpirun\n", frnn::app::launcher_ranks());
        std::fflush(stderr);
        return 1;
    }
    frnn::view::view_options o;
    std::string solver;
    int dim = 0;
    std::size_t particles = 0;
    CLI::App app{"frnn-view: run a particle-fluid scene live (see docs/VIEWER.md for the controls)"};
    app.add_option("scene_file", o.scene_file, "Scene JSON file (see sim/scenes/)");
    std::string names;
    for (const auto& n : frnn::sim::builtin_scene_names()) names += (names.empty() ? "" : "|") + n;
    app.add_option("--scene", o.scene_name, "Shipped scene: " + names)->check(CLI::IsMember(frnn::sim::builtin_scene_names()));
    app.add_option("--solver", solver, "viscoelastic|sph (default: the scene's)")->check(CLI::IsMember({"viscoelastic", "sph"}));
    app.add_option("--dim", dim, "2|3 (default: the scene's)")->check(CLI::IsMember({2, 3}));
    app.add_option("--particles", particles, "Target particle count")->check(CLI::Range(std::size_t(1), std::size_t(1) << 22));
    app.add_option("--threads", o.threads, "Simulation threads (default: all)")->check(CLI::Range(1, 1024));
    app.add_option("--script", o.script_file, "JSON actions by frame; runs in lockstep (docs/VIEWER.md)");
    app.add_option("--screenshot", o.screenshot_file, "Write the last frame as PNG (with --frames)");
    app.add_option("--frames", o.frames, "Quit after N frames")->check(CLI::Range(1L, 1L << 40));
    app.add_option("--state", o.state_file, "Write the end state as JSON (particles, colliders, camera)");
    app.add_option("--width", o.width, "Window width in pixels")->check(CLI::Range(320, 8192));
    app.add_option("--height", o.height, "Window height in pixels")->check(CLI::Range(240, 8192));
    app.add_option("--slow-step-ms", o.slow_step_ms, "Testing: sleep this long before every step")->check(CLI::Range(0.0, 60000.0));
    app.add_flag("--paused", o.paused, "Start paused");
    app.add_flag("--timing", o.timing, "Print mean simulation, copy, upload and drawing times and the median frame and step at the end");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);
        std::fprintf(stderr, "frnn-view: %s\n", e.what());
        return 2;
    }
    if (!o.screenshot_file.empty() && o.frames <= 0) {
        std::fprintf(stderr, "frnn-view: --screenshot needs --frames N\n");
        return 2;
    }
    try {
        if (!solver.empty()) o.overrides.solver = solver == "sph" ? frnn::sim::solver_kind::sph : frnn::sim::solver_kind::viscoelastic;
        if (dim) o.overrides.dim = dim;
        if (particles) o.overrides.particles = particles;
        const frnn::sim::scene s = load(o);
        frnn::view::viewer v(s, o);
        return v.run();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "frnn-view: error: %s\n", e.what());
        return 1;
    }
}
