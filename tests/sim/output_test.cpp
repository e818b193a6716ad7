// Output: PNG round trip and rendering, VTK frames, the run directory, resume from a
// checkpoint with no frame lost or duplicated, and the Chrome trace.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"
#include "frnn/sim/run.hpp"
#include "scratch_dir.hpp"

using namespace frnn::sim;
using frnn::test::scratch_dir;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}
run_options quiet(const fs::path& dir) {
    run_options o;
    o.out_dir = dir.string();
    o.progress = false;
    o.print_table = false;
    o.threads = 2;
    return o;
}
scene_overrides small(int dim, std::size_t n, std::uint64_t steps, int every) {
    scene_overrides o;
    o.dim = dim;
    o.particles = n;
    o.steps = steps;
    o.every = every;
    return o;
}
}  // namespace

TEST(SimOutput, PngRoundTrip) {
    image img;
    img.width = 300;
    img.height = 257;  // more than 64 KiB of scanlines
    img.rgb.resize(std::size_t(img.width) * std::size_t(img.height) * 3);
    for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = std::uint8_t(i * 7 + i / 1000);
    const std::string png = encode_png(img);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    const image back = decode_png(png);
    EXPECT_EQ(back.width, img.width);
    EXPECT_EQ(back.height, img.height);
    EXPECT_EQ(back.rgb, img.rgb);
    std::string bad = png;
    bad[40] ^= 1;
    EXPECT_THROW(decode_png(bad), frnn::error);
}

// A frame is mostly background: compressed, it takes a small part of its raw size.
TEST(SimOutput, PngCompressesAFlatFrame) {
    image img;
    img.width = 960;
    img.height = 540;
    img.rgb.assign(std::size_t(img.width) * std::size_t(img.height) * 3, 30);
    for (std::size_t i = 0; i < img.rgb.size(); i += 3001) img.rgb[i] = 200;  // a few specks
    const std::string png = encode_png(img);
    EXPECT_LT(png.size(), img.rgb.size() / 20);
    EXPECT_EQ(decode_png(png).rgb, img.rgb);
}

TEST(SimOutput, RunWritesFramesSeriesSummaryAndPictures) {
    const scratch_dir dir("sim_run");
    run_options o = quiet(dir);
    o.png = true;
    const auto r = run(builtin_scene_text("dam-break"), "dam-break", small(3, 3000, 12, 4), o);
    EXPECT_TRUE(r.finished);
    EXPECT_EQ(r.steps, 12u);
    EXPECT_EQ(r.frames, 4u);  // steps 0, 4, 8, 12
    for (int k = 0; k < 4; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d", k);
        EXPECT_TRUE(fs::exists(dir / "frames" / (std::string(name) + ".vtp"))) << name;
        const image img = decode_png(slurp(dir / "png" / (std::string(name) + ".png")));
        EXPECT_EQ(img.width, 960);
        // Fluid is drawn: some pixels are clearly blue, unlike the grey background.
        std::size_t blue = 0;
        for (std::size_t i = 0; i < img.rgb.size(); i += 3) blue += img.rgb[i + 2] > img.rgb[i] + 60;
        EXPECT_GT(blue, 1000u) << name;
    }
    const std::string vtp = slurp(dir / "frames" / "frame_00003.vtp");
    EXPECT_NE(vtp.find("NumberOfPoints=\"" + std::to_string(r.particles) + "\""), std::string::npos);
    for (const char* field : {"Name=\"velocity\"", "Name=\"density\"", "Name=\"pressure\"", "Name=\"Points\""})
        EXPECT_NE(vtp.find(field), std::string::npos) << field;
    const std::string pvd = slurp(dir / "particles.pvd");
    EXPECT_NE(pvd.find("frames/frame_00003.vtp"), std::string::npos);
    const auto summary = nlohmann::json::parse(slurp(dir / "summary.json"));
    EXPECT_EQ(summary["particles"], r.particles);
    EXPECT_EQ(summary["steps"], 12);
    EXPECT_TRUE(summary["mean_ms_per_step"].contains("density relaxation"));
    EXPECT_TRUE(summary["mean_ms_per_step"].contains("grid build + reorder"));
}

TEST(SimOutput, ResumeLosesAndDuplicatesNoFrame) {
    const scratch_dir full("sim_full"), cut("sim_cut");
    const std::string text = builtin_scene_text("droplet");
    const auto ov = small(2, 800, 40, 4);
    run(text, "droplet", ov, quiet(full));
    run_options o = quiet(cut);
    o.stop_after = 23;  // interrupted between checkpoints (every 5 frames = 20 steps)
    const auto first = run(text, "droplet", ov, o);
    EXPECT_FALSE(first.finished);
    const auto second = resume(cut.string(), quiet(cut));
    EXPECT_TRUE(second.finished);
    EXPECT_EQ(second.steps, 40u);
    EXPECT_EQ(second.frames, 11u);
    const std::string pvd = slurp(cut / "particles.pvd");
    EXPECT_EQ(pvd, slurp(full / "particles.pvd"));
    for (int k = 0; k <= 10; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.vtp", k);
        EXPECT_EQ(slurp(cut / "frames" / name), slurp(full / "frames" / name)) << name;
        const std::string entry = std::string("frames/") + name;
        EXPECT_EQ(pvd.find(entry), pvd.rfind(entry)) << "duplicate " << name;
    }
}

// WCSPH with wall particles: the density pass reads the walls' last extrapolated state, which
// the checkpoint must hold for the resumed run to match; with the continuity equation the
// density too is state.
TEST(SimOutput, ResumedWcsphWithWallParticlesIsTheUninterruptedRun) {
    const std::string shipped = builtin_scene_text("dam-break");
    std::string continuity = shipped;
    const std::string walls = R"("wall_particles": true,)";
    ASSERT_NE(continuity.find(walls), std::string::npos);
    continuity.replace(continuity.find(walls), walls.size(), walls + R"( "density": "continuity",)");
    for (const std::string& text : {shipped, continuity}) {
        SCOPED_TRACE(text == shipped ? "summation" : "continuity");
        const scratch_dir full("sim_wcsph_full"), cut("sim_wcsph_cut");
        scene_overrides ov = small(2, 800, 60, 6);  // checkpoints every 5 frames: at step 30
        ov.solver = solver_kind::sph;
        run(text, "dam-break", ov, quiet(full));
        run_options o = quiet(cut);
        o.stop_after = 41;
        EXPECT_FALSE(run(text, "dam-break", ov, o).finished);
        EXPECT_TRUE(resume(cut.string(), quiet(cut)).finished);
        EXPECT_EQ(slurp(cut / "checkpoint.bin"), slurp(full / "checkpoint.bin"));
        EXPECT_EQ(slurp(cut / "frames" / "frame_00010.vtp"), slurp(full / "frames" / "frame_00010.vtp"));
    }
}

TEST(SimOutput, ChromeTraceHasSpansPerStageAndThread) {
    const scratch_dir dir("sim_trace");
    run_options o = quiet(dir);
    o.trace_path = (dir / "trace.json").string();
    o.write_frames = false;
    // A worker joins the loops it is awake for: on a busy machine it may miss some, and now and
    // then all of a short run's, so the run is repeated until it shows up (normally at once).
    // Missing all the loops of 100 runs is out of reach of any load, while a worker that never
    // runs a chunk, or whose spans are lost, still fails. Spans carry worker numbers 0 and 1 only.
    constexpr int attempts = 100;
    std::set<int> threads;
    for (int attempt = 0; attempt < attempts && threads.size() < 2; ++attempt) {
        run(builtin_scene_text("dam-break"), "dam-break", small(2, 20000, 5, 5), o);
        const auto trace = nlohmann::json::parse(slurp(dir / "trace.json"));
        std::set<std::string> stages;
        threads.clear();
        for (const auto& e : trace["traceEvents"])
            if (e["ph"] == "X") {
                stages.insert(e["name"].get<std::string>());
                threads.insert(e["tid"].get<int>());
            }
        for (const char* stage : {"density relaxation", "collisions", "viscosity"})
            ASSERT_TRUE(stages.count(stage)) << stage;
        ASSERT_TRUE(threads.count(0)) << "no span of the calling thread";
        ASSERT_LE(threads.size(), 2u) << "a worker number beyond 0 and 1";
    }
    EXPECT_EQ(threads, (std::set<int>{0, 1})) << "worker 1 ran no traced chunk in " << attempts << " runs";
}
