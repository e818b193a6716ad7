// `frnn sim`: runs a particle-fluid scene (viscoelastic or SPH) and writes VTK frames, a
// ParaView series, a summary and optionally PNG pictures, a video and a Chrome trace. With no
// argument it runs the default 3D viscoelastic dam break of 32,768 particles.
// Usage errors throw CLI::ValidationError (exit 2); bad scenes throw frnn::error (exit 1).
#ifdef FRNN_SIM_AVAILABLE
#include <fstream>
#include <sstream>
#include <string>

#include "command.hpp"
#include "contend_options.hpp"
#include "launcher.hpp"
#include "sim_mpi.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/run.hpp"
#include "frnn/sim/scene.hpp"

namespace frnn::app {
namespace {

struct sim_args {
    std::string scene_file, scene_name, solver, out, trace, resume;
    int dim = 0, every = 0, threads = 0;
    std::size_t particles = 0;
    std::uint64_t steps = 0;
    double time = -1;
    bool png = false, video = false, quiet = false;
    sim::balance_options balance;
    contend_args contend;
};

void run_sim(const sim_args& a) {
    sim::run_options opt;
    // Forked (--contend-process) before the particles exist; lives until the run has ended.
    const auto load = a.contend.make();
    if (load) opt.load = {[&load](bool busy) { busy ? load->busy() : load->quiet(); }, 10, load_label(*load)};
    opt.out_dir = a.out;
    opt.threads = a.threads;
    opt.trace_path = a.trace;
    opt.png = a.png || a.video;
    opt.video = a.video;
    opt.progress = !a.quiet;
    opt.balance = a.balance;
    if (!a.resume.empty()) {
        if (!a.scene_file.empty() || !a.scene_name.empty() || !a.solver.empty() || a.dim || a.particles || a.steps ||
            a.time >= 0 || a.every)
            throw CLI::ValidationError("--resume", "continues a run with its own scene; give no scene options with it");
        const auto resume = [&](const sim::run_options& o) { sim::resume(a.resume, o); };
        if (launcher_ranks() > 1) return run_sim_across_ranks(opt, resume);
        resume(opt);
        return;
    }
    if (!a.scene_file.empty() && !a.scene_name.empty())
        throw CLI::ValidationError("--scene", "give either a scene file or --scene, not both");
    sim::scene_overrides ov;
    if (!a.solver.empty()) ov.solver = a.solver == "sph" ? sim::solver_kind::sph : sim::solver_kind::viscoelastic;
    if (a.dim) ov.dim = a.dim;
    if (a.particles) ov.particles = a.particles;
    if (a.steps) ov.steps = a.steps;
    if (a.time >= 0) ov.duration = a.time;
    if (a.every) ov.every = a.every;
    const auto run = [&](const sim::run_options& o) {
        std::string text, origin;
        sim::on_every_rank(o.ranks, [&] {  // a node that cannot read the file stops every rank
            if (!a.scene_file.empty()) {
                std::ifstream in(a.scene_file, std::ios::binary);
                if (!in) throw frnn::error("cannot open scene file '" + a.scene_file + "'");
                std::stringstream ss;
                ss << in.rdbuf();
                text = ss.str();
                origin = a.scene_file;
            } else {
                const std::string name = a.scene_name.empty() ? "dam-break" : a.scene_name;
                text = sim::builtin_scene_text(name);
                origin = "scene " + name;
            }
        });
        sim::run(text, origin, ov, o);
    };
    if (launcher_ranks() > 1) return run_sim_across_ranks(opt, run);
    run(opt);
}

const register_command reg{"sim", [](CLI::App& app) {
    auto args = std::make_shared<sim_args>();
    auto* c = app.add_subcommand("sim", "Run a particle-fluid simulation (default: 3D viscoelastic dam break, 32,768 particles)");
    c->add_option("scene_file", args->scene_file, "Scene JSON file (see sim/scenes/)");
    std::string names;
    for (const auto& n : sim::builtin_scene_names()) names += (names.empty() ? "" : "|") + n;
    c->add_option("--scene", args->scene_name, "Shipped scene: " + names)->check(CLI::IsMember(sim::builtin_scene_names()));
    c->add_option("--solver", args->solver, "viscoelastic|sph (default: the scene's)")->check(CLI::IsMember({"viscoelastic", "sph"}));
    c->add_option("--dim", args->dim, "2|3 (default: the scene's)")->check(CLI::IsMember({2, 3}));
    c->add_option("--particles", args->particles, "Target particle count")->check(CLI::Range(std::size_t(1), std::size_t(1) << 26));
    auto* steps = c->add_option("--steps", args->steps, "Run exactly S steps")->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 40));
    auto* time = c->add_option("--time", args->time, "Simulated seconds (default: the scene's duration)")->check(CLI::NonNegativeNumber);
    steps->excludes(time);
    c->add_option("--out", args->out, "Output folder (default: a new folder named after the scene and time)");
    c->add_option("--every", args->every, "Write a frame every K steps (default: the scene's fps)")->check(CLI::Range(1, 1 << 30));
    c->add_option("--threads", args->threads, "Threads (default: all)")->check(CLI::Range(1, 1024));
    c->add_option("--trace", args->trace, "Write a Chrome trace JSON (chrome://tracing, Perfetto)");
    c->add_flag("--png", args->png, "Also render png/frame_NNNNN.png");
    c->add_flag("--video", args->video, "Also make particles.mp4 with ffmpeg (implies --png)");
    c->add_option("--resume", args->resume, "Continue the interrupted run in DIR from its last checkpoint");
    c->add_flag("--quiet", args->quiet, "No progress on stderr");
    c->add_option("--imbalance", args->balance.imbalance,
                  "Under mpirun: cut the domain anew when the most loaded rank holds more than (1 + this) times "
                  "the mean (default 0.1)")
        ->check(CLI::Range(0.0, 1e6));
    c->add_option("--balance-every", args->balance.check_every,
                  "Under mpirun: steps between balance checks, 0 for never (default 20)");
    add_contend_options(c, args->contend, "in every other block of 10 steps (columns quiet/contended in the table)");
    c->callback([args] { run_sim(*args); });
}};

}  // namespace
}  // namespace frnn::app
#endif
