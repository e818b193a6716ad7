// Video: `frnn sim --video` (run_options::video) makes particles.mp4 with one video frame per
// PNG frame at the PNGs' size, checked with ffprobe; encode_video takes any path and leaves
// nothing behind when ffmpeg fails. Skipped, with the reason, where ffmpeg is not installed
// (scripts/setup installs it).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/run.hpp"
#include "frnn/sim/video.hpp"
#include "scratch_dir.hpp"

using namespace frnn::sim;
using frnn::test::scratch_dir;
namespace fs = std::filesystem;

namespace {

// ffprobe's count of decoded frames and the size of the first video stream.
nlohmann::json probe(const fs::path& mp4) {
    std::string quoted = "'";
    for (char c : mp4.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    quoted += "'";
    const std::string cmd = "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
                            "stream=nb_read_frames,width,height,codec_name -of json " + quoted;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return {};
    std::string out;
    char buf[4096];
    for (std::size_t got; (got = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, got);
    if (pclose(p) != 0) return {};
    return nlohmann::json::parse(out).at("streams").at(0);
}

std::size_t files_in(const fs::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

TEST(SimVideo, RunMakesOneVideoFramePerPicture) {
    if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed";
    const scratch_dir dir("sim video 'quoted'");  // a space and quotes: no shell in between
    run_options o;
    o.out_dir = dir.string();
    o.progress = false;
    o.print_table = false;
    o.threads = 2;
    o.video = true;
    scene_overrides ov;
    ov.dim = 2;
    ov.particles = 600;
    ov.steps = 20;
    ov.every = 4;
    const auto r = run(builtin_scene_text("droplet"), "droplet", ov, o);
    ASSERT_EQ(r.frames, 6u);  // steps 0, 4, ..., 20
    ASSERT_EQ(files_in(dir / "png"), r.frames);
    const auto stream = probe(dir / "particles.mp4");
    ASSERT_FALSE(stream.is_null()) << "ffprobe could not read particles.mp4";
    EXPECT_EQ(stream.at("codec_name"), "h264");
    EXPECT_EQ(std::stoul(stream.at("nb_read_frames").get<std::string>()), r.frames);
    EXPECT_EQ(stream.at("width"), 960);
    EXPECT_EQ(stream.at("height"), 540);
}

TEST(SimVideo, FailureLeavesNoFile) {
    if (!ffmpeg_available()) GTEST_SKIP() << "ffmpeg is not installed";
    const scratch_dir dir("sim_video_fail");
    fs::create_directories(dir / "png");  // no frames in it
    try {
        encode_video((dir / "png").string(), 25, (dir / "out.mp4").string());
        ADD_FAILURE() << "no frames, yet a video";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("ffmpeg could not make"), std::string::npos) << e.what();
    }
    EXPECT_EQ(files_in(dir), 1u);  // png/ only: no video, no temporary
    EXPECT_THROW(encode_video((dir / "png").string(), 0, (dir / "out.mp4").string()), frnn::error);
}
