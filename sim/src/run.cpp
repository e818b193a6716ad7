// The run loop: steps, frames, front record, checkpoints, progress, timing table, summary.
#include "frnn/sim/run.hpp"
#include "frnn/sim/video.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/parallel.hpp"
#include "frnn/sim/martin_moyce.hpp"
#include "frnn/sim/output.hpp"
#include "frnn/sim/solver.hpp"
#include "checkpoint.hpp"
#include "particle_solver.hpp"

namespace frnn::sim {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using run_state = detail::checkpoint_header;

void save_checkpoint(const std::string& dir, const run_state& st, const solver& sol) {
    detail::write_checkpoint(dir + "/checkpoint.bin", st, sol);
}

std::string frame_name(std::size_t k, const char* ext) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "frame_%05zu.%s", k, ext);
    return buf;
}

std::string timestamp() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
    return buf;
}

/// Surge front along the probe axis, in units of a, from the particles' extent (across ranks a
/// collective call: a largest coordinate over the ranks, not a gather).
double front_Z(solver& sol, const front_probe& f) {
    return (sol.largest_coordinate(f.axis) + sol.spacing() / 2 - f.origin) / f.a;
}

class progress_meter {
public:
    explicit progress_meter(bool enabled) : on_(enabled), tty_(enabled && ::isatty(2)) {}
    void update(double frac, std::uint64_t step, double t, double wall, std::size_t frame, bool frame_written) {
        if (!on_) return;
        const double rate = wall > 0 ? double(step - first_step_) / wall : 0;
        const double eta = frac > 0 ? wall * (1 - frac) / std::max(1e-9, frac - first_frac_) : 0;
        if (tty_) {
            if (wall - last_ < 0.1 && frac < 1) return;
            last_ = wall;
            const int width = 30, fill = int(std::clamp(frac, 0.0, 1.0) * width);
            std::fprintf(stderr, "\r[%s%s] %3.0f%% step %llu  t=%.3f s  %.1f steps/s  ETA %.0f s   ",
                         std::string(std::size_t(fill), '#').c_str(), std::string(std::size_t(width - fill), '.').c_str(),
                         100 * frac, (unsigned long long)step, t, rate, eta);
            if (frac >= 1) std::fprintf(stderr, "\n");
        } else if (frame_written) {
            std::fprintf(stderr, "frame %zu: step %llu, t = %.4f s, %.0f%%, %.1f steps/s, ETA %.0f s\n", frame,
                         (unsigned long long)step, t, 100 * frac, rate, eta);
        }
    }
    void start(std::uint64_t step, double frac) { first_step_ = step, first_frac_ = frac; }

private:
    bool on_, tty_;
    double last_ = -1, first_frac_ = 0;
    std::uint64_t first_step_ = 0;
};

// --video: particles.mp4 from the PNG frames, or a message when ffmpeg is missing (the run
// itself has succeeded; its frames stay).
void make_video(const std::string& dir, double fps) {
    if (!ffmpeg_available()) {
        std::fprintf(stderr, "frnn sim: --video: ffmpeg is not installed (apt-get install ffmpeg); the PNG frames are in %s/png\n",
                     dir.c_str());
        return;
    }
    encode_video(dir + "/png", fps, dir + "/particles.mp4");
    std::fprintf(stderr, "video: %s/particles.mp4\n", dir.c_str());
}

// The line above the table under a load: what ran, and how many blocks, or that too few did.
std::string load_line(const profiler& prof, const load_hook& load) {
    const std::uint64_t b = load.block_steps;
    std::string s = "under load (" + load.label + "): blocks of " + std::to_string(b) + " steps after " + std::to_string(b) +
                    " warm-up steps, quiet and contended in turn; ";
    const std::string counts = std::to_string(prof.blocks(false)) + " quiet and " + std::to_string(prof.blocks(true)) + " contended blocks";
    if (prof.enough_blocks()) return s + "medians over " + counts + "\n";
    return s + "TOO SHORT TO COMPARE: " + counts + ", at least " + std::to_string(profiler::min_blocks) +
           " of each are needed (run at least " + std::to_string(b * (1 + 2 * profiler::min_blocks)) + " steps)\n";
}

// summary.json's "under_load": the blocks and, when there are enough, the medians by stage.
json load_summary(const profiler& prof, const load_hook& load) {
    json j;
    j["load"] = load.label;
    j["block_steps"] = load.block_steps;
    j["warm_up_steps"] = load.block_steps;
    j["quiet_blocks"] = prof.blocks(false);
    j["contended_blocks"] = prof.blocks(true);
    j["enough_blocks"] = prof.enough_blocks();
    if (!prof.enough_blocks()) return j;
    json quiet = json::object(), contended = json::object(), ratio = json::object();
    const auto put = [&](const std::string& name, double q, double c) {
        quiet[name] = q;
        contended[name] = c;
        ratio[name] = q > 0 ? json(c / q) : json(nullptr);
    };
    for (std::size_t s = 0; s < std::size_t(stage::count); ++s)
        if (prof.total_seconds(stage(s)) > 0 && stage(s) != stage::output)
            put(to_string(stage(s)), prof.block_median_ms(false, stage(s)), prof.block_median_ms(true, stage(s)));
    put("step without output", prof.block_median_step_ms(false), prof.block_median_step_ms(true));
    j["quiet_ms_per_step"] = quiet;
    j["contended_ms_per_step"] = contended;
    j["contended_over_quiet"] = ratio;
    return j;
}

// What a run returns: its totals and the profiler's mean ms per step by stage (with the block
// medians under a load).
run_result result_of(solver& sol, profiler& prof, const run_state& st, const std::string& dir, double wall,
                     bool finished) {
    run_result res;
    res.out_dir = dir;
    res.steps = sol.steps();
    res.particles = sol.view().n;
    res.wall_particles = sol.wall_particle_count();
    res.frames = st.frames.size();
    res.sim_time = sol.time();
    res.wall_seconds = wall;
    res.step_ms = prof.mean_step_ms();
    res.front = st.front;
    res.finished = finished;
    for (std::size_t s = 0; s < std::size_t(stage::count); ++s)
        if (prof.total_seconds(stage(s)) > 0) res.stage_ms.emplace_back(to_string(stage(s)), prof.mean_ms(stage(s)));
    res.quiet_blocks = prof.blocks(false);
    res.contended_blocks = prof.blocks(true);
    if (prof.enough_blocks()) {
        res.quiet_step_ms = prof.block_median_step_ms(false);
        res.contended_step_ms = prof.block_median_step_ms(true);
    }
    return res;
}

// summary.json, and front.csv with the errors against Martin & Moyce (into res) when the scene
// records the surge front.
void write_summary(const std::string& dir, solver& sol, profiler& prof, const run_state& st, run_result& res,
                   const run_options& opt, int threads, std::uint64_t this_run, bool resumed) {
    const scene& sc = sol.get_scene();
    json summary;
    summary["scene"] = sc.name;
    summary["solver"] = to_string(sc.solver);
    summary["dim"] = sc.dim;
    summary["particles"] = res.particles;
    summary["wall_particles"] = res.wall_particles;
    summary["steps"] = res.steps;
    summary["steps_this_run"] = this_run;
    summary["simulated_seconds"] = res.sim_time;
    summary["threads"] = threads;
    if (const ranks_report ranks = sol.report_ranks(); !ranks.per_rank.empty()) {
        json per_rank = json::array();
        std::size_t total = 0;
        for (const auto& r : ranks.per_rank) total += r.particles;
        for (const auto& r : ranks.per_rank)
            per_rank.push_back({{"particles", r.particles},
                                {"load", total ? double(r.particles * ranks.per_rank.size()) / double(total) : 0.0},
                                {"ghosts", r.ghosts},
                                {"bytes_sent", r.bytes_sent},
                                {"exchange_ms_per_step", r.exchange_ms},
                                {"waiting_ms_per_step", r.waiting_ms},
                                {"local_ms_per_step", r.local_ms}});
        summary["ranks"] = {{"count", ranks.per_rank.size()},
                            {"per_rank", per_rank},
                            {"balance",
                             {{"imbalance", opt.balance.imbalance},
                              {"check_every", opt.balance.check_every},
                              {"checks", ranks.checks},
                              {"rebalances", ranks.rebalances},
                              {"largest_imbalance", ranks.largest_imbalance},
                              {"mean_imbalance", ranks.mean_imbalance}}}};
    }
    summary["spacing"] = sol.spacing();
    summary["radius"] = sol.radius();
    summary["rest_density"] = sol.rest_density();
    summary["frames"] = res.frames;
    summary["wall_seconds"] = res.wall_seconds;
    summary["resumed"] = resumed;
    json stages = json::object(), cpu = json::object();
    for (const auto& [name, ms] : res.stage_ms) stages[name] = ms;
    for (std::size_t s = 0; s < std::size_t(stage::count); ++s)
        if (prof.total_seconds(stage(s)) > 0) cpu[to_string(stage(s))] = prof.mean_cpu_ms(stage(s));
    summary["mean_ms_per_step"] = stages;
    summary["mean_process_cpu_ms_per_step"] = cpu;
    summary["step_ms_without_output"] = res.step_ms;
    if (opt.load.set) summary["under_load"] = load_summary(prof, opt.load);
    if (sc.front.enabled && !st.front.empty()) {
        std::ostringstream csv;
        csv.precision(6);
        csv << "T,Z\n";
        for (const auto& [T, Z] : st.front) csv << T << ',' << Z << '\n';
        io::write_file_atomically(dir + "/front.csv", csv.str());
        // Per series, {"a_inches", "error"}; null when the run ends before T = front_error_t_hi.
        json errors = nullptr;
        try {
            std::vector<double> found;
            for (const auto& series : martin_moyce()) found.push_back(front_error(st.front, series));
            errors = json::array();
            for (std::size_t k = 0; k < found.size(); ++k)
                errors.push_back({{"a_inches", martin_moyce()[k].a_inches}, {"error", found[k]}});
            res.front_errors = found;
        } catch (const error&) {
        }
        summary["martin_moyce"] = {{"T_range", {front_error_t_lo, front_error_t_hi}}, {"series", errors}};
    }
    io::write_file_atomically(dir + "/summary.json", summary.dump(2) + "\n");
}

// The lines and the per-stage table printed at the end of a run.
void print_report(const scene& sc, profiler& prof, const run_result& res, const run_options& opt, int threads,
                  const std::string& dir) {
    std::printf("%s: %zu particles, %s %dD, %llu steps, %.3f s simulated in %.2f s on %d threads%s\n", sc.name.c_str(),
                res.particles, to_string(sc.solver).c_str(), sc.dim, (unsigned long long)res.steps, res.sim_time,
                res.wall_seconds, threads,
                opt.ranks && opt.ranks->size() > 1 ? (" per rank, " + std::to_string(opt.ranks->size()) + " ranks").c_str() : "");
    if (res.wall_particles > 0) std::printf("walls: %zu wall particles\n", res.wall_particles);
    if (opt.load.set) std::printf("%s", load_line(prof, opt.load).c_str());
    std::printf("%s", prof.table(bool(opt.load.set)).c_str());
    if (!res.front_errors.empty()) {
        std::printf("surge front vs Martin & Moyce (1952), mean relative error over T in [%g, %g]:", front_error_t_lo,
                    front_error_t_hi);
        for (std::size_t k = 0; k < res.front_errors.size(); ++k)
            std::printf("%s %.1f%% (a = %g in)", k ? "," : "", 100 * res.front_errors[k], martin_moyce()[k].a_inches);
        std::printf(" (%s/front.csv)\n", dir.c_str());
    }
    std::printf("output: %s (particles.pvd opens in ParaView)\n", dir.c_str());
}

run_result execute(run_state& st, solver& sol, const run_options& opt, const std::string& dir, bool resumed) {
    const scene& sc = sol.get_scene();
    // Across ranks, rank 0 writes and prints; every rank calls gather() at the same points.
    const bool root = !opt.ranks || opt.ranks->rank() == 0;
    const int threads = resolve_thread_count(opt.threads);
    profiler prof(!opt.trace_path.empty(), threads);
    const double g = std::sqrt(sc.gravity[0] * sc.gravity[0] + sc.gravity[1] * sc.gravity[1] + sc.gravity[2] * sc.gravity[2]);
    const double height = sc.domain_max[1] - sc.domain_min[1];
    const double color_speed = std::max(0.5, std::sqrt(2 * std::max(g, 1e-3) * height));
    const double frame_dt = 1 / sc.output.fps;
    std::size_t frames_since_checkpoint = 0;
    const bool under_load = bool(opt.load.set);
    const std::uint64_t block = opt.load.block_steps;
    if (under_load && block == 0) throw error("run_options: load.block_steps must be > 0");
    // Block k starts at step k * block of this run: block 0 warms up, then quiet and busy in turn.
    auto start_block = [&](std::uint64_t k) {
        prof.end_block();
        if (k == 0) return;
        opt.load.set(k % 2 == 0);
        prof.start_block(k % 2 == 0);
    };

    auto write_frame = [&] {
        const stage_timer timer(prof, stage::output);
        const std::size_t k = st.frames.size();
        const std::string vtp = "frames/" + frame_name(k, "vtp");
        // Across ranks every rank writes its part of the frame; the pictures are drawn on
        // rank 0 from the gathered particles.
        const bool across = opt.ranks && opt.ranks->size() > 1;
        if (opt.write_frames && across) write_vtp(dir + "/" + vtp, sol.id_share(), *opt.ranks);
        const bool pictures = opt.png || opt.video;
        if (pictures) sol.gather();
        if (!root) {
            st.frames.emplace_back(sol.time(), "");
            return;
        }
        if (opt.write_frames) {
            if (!across) write_vtp(dir + "/" + vtp, sol.view());
            st.frames.emplace_back(sol.time(), vtp);
            write_pvd(dir + "/particles.pvd", st.frames);
        } else {
            st.frames.emplace_back(sol.time(), "");
        }
        if (pictures)
            io::write_file_atomically(dir + "/png/" + frame_name(k, "png"),
                                      encode_png(render(sol.view(), sc, 0.5 * sol.spacing(), 960, 540, color_speed, sol.time())));
    };
    auto record_front = [&] {
        if (!sc.front.enabled) return;
        const double T = sol.time() * std::sqrt(2 * g / sc.front.a);
        if (T + 1e-12 < st.next_front_T) return;
        st.front.emplace_back(T, front_Z(sol, sc.front));
        while (st.next_front_T <= T + 1e-12) st.next_front_T += sc.front.every_T;
    };
    auto done = [&] {
        if (sc.steps > 0) return sol.steps() >= sc.steps;
        return sol.time() >= sc.duration * (1 - 1e-9) - 1e-12;
    };
    auto fraction = [&] {
        if (sc.steps > 0) return double(sol.steps()) / double(sc.steps);
        return sc.duration > 0 ? std::min(1.0, sol.time() / sc.duration) : 1.0;
    };

    if (!resumed) {
        write_frame();
        st.next_frame_time = frame_dt;
        record_front();
    }
    progress_meter meter(opt.progress);
    meter.start(sol.steps(), fraction());
    const auto wall0 = std::chrono::steady_clock::now();
    std::uint64_t this_run = 0;
    bool interrupted = false;
    while (!done()) {
        if (opt.stop_after && this_run >= opt.stop_after) {
            interrupted = true;
            break;
        }
        if (under_load && this_run % block == 0) start_block(this_run / block);
        sol.step(prof);
        ++this_run;
        bool frame_due = sc.output.every > 0 ? sol.steps() % std::uint64_t(sc.output.every) == 0
                                              : sol.time() >= st.next_frame_time - 1e-9 * frame_dt;
        if (done() && !frame_due && st.frames.size() > 0 && sc.output.every == 0) frame_due = true;
        if (frame_due) {
            if (sc.output.every == 0)
                while (st.next_frame_time <= sol.time() + 1e-9 * frame_dt) st.next_frame_time += frame_dt;
        }
        record_front();
        if (frame_due) {
            write_frame();
            if (++frames_since_checkpoint >= std::size_t(sc.output.checkpoint_every) && !done()) {
                const stage_timer timer(prof, stage::output);
                sol.gather();
                if (root) save_checkpoint(dir, st, sol);
                frames_since_checkpoint = 0;
            }
        }
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        meter.update(fraction(), sol.steps(), sol.time(), wall, st.frames.size() - 1, frame_due);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (under_load) {
        if (this_run % block == 0) prof.end_block();  // else the last block is incomplete: dropped
        opt.load.set(false);
    }

    sol.gather();
    run_result res = result_of(sol, prof, st, dir, wall, !interrupted);
    if (interrupted || !root) return res;

    save_checkpoint(dir, st, sol);
    write_summary(dir, sol, prof, st, res, opt, threads, this_run, resumed);
    if (!opt.trace_path.empty()) prof.write_trace(opt.trace_path);
    if (opt.print_table) print_report(sc, prof, res, opt, threads, dir);
    if (opt.video) make_video(dir, sc.output.every > 0 ? 1 / (sol.last_dt() * sc.output.every) : sc.output.fps);
    return res;
}

void prepare_dir(const std::string& dir, const run_options& opt, bool fresh) {
    std::error_code ec;
    fs::create_directories(dir + "/frames", ec);
    if (ec) throw error("cannot create output folder '" + dir + "': " + ec.message());
    if (opt.png || opt.video) fs::create_directories(dir + "/png", ec);
    if (!fresh) return;
    // A new run in an old folder: drop that folder's old frames (ours only) so none is stale.
    for (const char* sub : {"frames", "png"}) {
        if (!fs::exists(dir + "/" + sub)) continue;
        for (const auto& e : fs::directory_iterator(dir + "/" + sub)) {
            const std::string n = e.path().filename().string();
            if (n.rfind("frame_", 0) == 0 && (e.path().extension() == ".vtp" || e.path().extension() == ".png")) fs::remove(e.path(), ec);
        }
    }
    fs::remove(dir + "/front.csv", ec);
    fs::remove(dir + "/checkpoint.bin", ec);
}

}  // namespace

run_result run(const std::string& scene_json, const std::string& origin, const scene_overrides& overrides, const run_options& opt) {
    run_state st{scene_json, origin, overrides, {}, 0, {}, 0};
    const bool root = !opt.ranks || opt.ranks->rank() == 0;
    scene sc;
    std::unique_ptr<solver> sol;
    std::string dir = opt.out_dir;
    on_every_rank(opt.ranks, [&] {
        sc = parse_scene(scene_json, origin);
        apply(sc, overrides);
        sol = make_solver(sc, opt.threads);
        if (opt.ranks && opt.ranks->size() > 1) sol->set_ranks(opt.ranks, opt.balance);
        if (!root) return;
        if (dir.empty()) {
            dir = "sim-" + sc.name + "-" + to_string(sc.solver) + "-" + std::to_string(sc.dim) + "d-" + timestamp();
            for (int k = 2; fs::exists(dir); ++k) dir = dir.substr(0, dir.rfind("~")) + "~" + std::to_string(k);
        }
        prepare_dir(dir, opt, true);
    });
    if (opt.progress && root)
        std::fprintf(stderr, "frnn sim: %s, %s %dD, %zu particles (spacing %.4g, radius %.4g) -> %s\n", sc.name.c_str(),
                     to_string(sc.solver).c_str(), sc.dim, sol->view().n, sol->spacing(), sol->radius(), dir.c_str());
    return execute(st, *sol, opt, dir, false);
}

run_result resume(const std::string& dir, const run_options& opt) {
    const bool root = !opt.ranks || opt.ranks->rank() == 0;
    run_state st;
    std::unique_ptr<solver> sol;
    on_every_rank(opt.ranks, [&] {  // across ranks, every rank reads the checkpoint
        std::ifstream in(dir + "/checkpoint.bin", std::ios::binary);
        if (!in) throw error("--resume: no checkpoint in '" + dir + "' (expected " + dir + "/checkpoint.bin)");
        st = detail::read_checkpoint_header(in, "--resume: '" + dir + "/checkpoint.bin'");
        scene sc = parse_scene(st.scene_json, st.origin);
        apply(sc, st.ov);
        sol = make_solver(sc, opt.threads);
        sol->load(in);
        if (opt.ranks && opt.ranks->size() > 1) sol->set_ranks(opt.ranks, opt.balance);
        if (!root) return;
        prepare_dir(dir, opt, false);
        if (opt.write_frames && !st.frames.empty()) write_pvd(dir + "/particles.pvd", st.frames);
    });
    if (opt.progress && root)
        std::fprintf(stderr, "frnn sim: resuming %s at step %llu (t = %.4f s, frame %zu)\n", dir.c_str(),
                     (unsigned long long)sol->steps(), sol->time(), st.frames.empty() ? 0 : st.frames.size() - 1);
    return execute(st, *sol, opt, dir, true);
}

}  // namespace frnn::sim
