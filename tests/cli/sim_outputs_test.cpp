// `frnn sim --png`, `--trace` and `--time` on small 2D dam breaks: one well-formed PNG per
// frame (the frames the VTK files and summary.json count), a Chrome trace that parses and has
// spans of every stage the summary timed in every step, and a run that stops at the first step
// that reaches the simulated time (the same time as that many --steps, later than one fewer).
#include "cli/run_tool.hpp"

#ifdef FRNN_TOOL_HAS_SIM
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>

namespace frnn::test {
namespace {

const std::string small_scene = "sim --scene dam-break --dim 2 --particles 300 --quiet ";

nlohmann::json read_json(const std::filesystem::path& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
}

/// The frame_*.<ext> files of a folder, by name.
std::vector<std::string> frames_in(const std::filesystem::path& folder, const std::string& ext) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(folder))
        if (e.path().extension() == ext) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::uint32_t big_endian(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = v << 8 | std::uint8_t(s[at + k]);
    return v;
}

/// CRC-32 of PNG chunks (ISO 3309, reflected, bit by bit: an implementation of our own).
std::uint32_t crc32(const std::string& s, std::size_t begin, std::size_t end) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = begin; i < end; ++i) {
        c ^= std::uint8_t(s[i]);
        for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
}

/// A whole PNG: the signature, chunks whose CRCs match, IHDR first (width x height, 8-bit
/// RGB), image data starting with a zlib header, IEND last with nothing after it.
::testing::AssertionResult valid_png(const std::string& png, std::uint32_t width, std::uint32_t height) {
    if (png.rfind("\x89PNG\r\n\x1a\n", 0) != 0) return ::testing::AssertionFailure() << "no PNG signature";
    std::size_t at = 8;
    std::vector<std::string> types;
    std::string idat;
    while (at + 12 <= png.size()) {
        const std::size_t length = big_endian(png, at);
        if (at + 12 + length > png.size()) return ::testing::AssertionFailure() << "chunk past the end at " << at;
        const std::string type = png.substr(at + 4, 4);
        if (crc32(png, at + 4, at + 8 + length) != big_endian(png, at + 8 + length))
            return ::testing::AssertionFailure() << "bad CRC in chunk " << type;
        if (type == "IHDR") {
            const std::string h = png.substr(at + 8, length);
            if (length != 13 || big_endian(h, 0) != width || big_endian(h, 4) != height || h[8] != 8 || h[9] != 2)
                return ::testing::AssertionFailure() << "IHDR is not " << width << "x" << height << " 8-bit RGB";
        }
        if (type == "IDAT") idat += png.substr(at + 8, length);
        types.push_back(type);
        at += 12 + length;
    }
    if (at != png.size()) return ::testing::AssertionFailure() << png.size() - at << " bytes after the last chunk";
    if (types.empty() || types.front() != "IHDR" || types.back() != "IEND")
        return ::testing::AssertionFailure() << "chunks do not run from IHDR to IEND";
    if (idat.size() < 2 || (std::uint8_t(idat[0]) & 0x0f) != 8 || (std::uint8_t(idat[0]) * 256 + std::uint8_t(idat[1])) % 31 != 0)
        return ::testing::AssertionFailure() << "image data without a zlib header";
    return ::testing::AssertionSuccess();
}

TEST(cli_sim_outputs, png_writes_one_valid_picture_per_frame) {
    const auto dir = fresh_dir();
    // 6 steps with a frame every 2: frames at steps 0, 2, 4 and 6.
    const tool_result r = run_tool(dir, small_scene + "--steps 6 --every 2 --threads 1 --out out --png");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<std::string> pngs = frames_in(dir / "out" / "png", ".png");
    EXPECT_EQ(pngs, (std::vector<std::string>{"frame_00000.png", "frame_00001.png", "frame_00002.png", "frame_00003.png"}));
    EXPECT_EQ(frames_in(dir / "out" / "frames", ".vtp").size(), pngs.size());
    EXPECT_EQ(read_json(dir / "out" / "summary.json").at("frames").get<std::size_t>(), pngs.size());
    for (const std::string& name : pngs) EXPECT_TRUE(valid_png(read_bytes(dir / "out" / "png" / name), 960, 540)) << name;
    // The pictures follow the fluid: the first and the last differ.
    EXPECT_NE(read_bytes(dir / "out" / "png" / pngs.front()), read_bytes(dir / "out" / "png" / pngs.back()));
    // Without --png there is no png folder.
    ASSERT_EQ(run_tool(dir, small_scene + "--steps 2 --threads 1 --out plain").code, 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "plain" / "png"));
}

TEST(cli_sim_outputs, trace_has_spans_of_every_timed_stage_in_every_step) {
    const auto dir = fresh_dir();
    const int steps = 5;
    const tool_result r = run_tool(dir, small_scene + "--steps " + std::to_string(steps) +
                                            " --every 1000 --threads 2 --out out --trace trace.json");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json summary = read_json(dir / "out" / "summary.json");
    const int threads = summary.at("threads").get<int>();
    EXPECT_EQ(threads, 2);
    nlohmann::json trace;
    ASSERT_NO_THROW(trace = read_json(dir / "trace.json")) << "the trace is not JSON";
    std::set<std::string> names;
    std::set<std::uint64_t> steps_seen;
    std::set<int> named_threads;
    std::size_t bad = 0;
    for (const auto& e : trace.at("traceEvents")) {
        if (e.at("ph") == "M") {
            named_threads.insert(e.at("tid").get<int>());
            continue;
        }
        EXPECT_EQ(e.at("ph"), "X") << e.dump();
        names.insert(e.at("name").get<std::string>());
        steps_seen.insert(e.at("args").at("step").get<std::uint64_t>());
        const int tid = e.at("tid").get<int>();
        bad += !(e.at("dur").get<double>() >= 0 && e.at("ts").get<double>() >= 0 && tid >= 0 && tid < threads);
    }
    EXPECT_EQ(bad, 0u) << "spans with a negative time or an unknown thread";
    EXPECT_EQ(named_threads.size(), std::size_t(threads));
    // Every stage the summary timed, but output (timed outside the steps, not traced).
    std::set<std::string> timed;
    for (const auto& [stage, ms] : summary.at("mean_ms_per_step").items())
        if (stage != "output") timed.insert(stage);
    EXPECT_EQ(names, timed);
    for (const char* stage : {"grid build + reorder", "neighbor lists", "integration"}) EXPECT_TRUE(names.count(stage)) << stage;
    std::set<std::uint64_t> all_steps;
    for (int s = 0; s < steps; ++s) all_steps.insert(std::uint64_t(s));
    EXPECT_EQ(steps_seen, all_steps);
}

TEST(cli_sim_outputs, time_stops_at_the_first_step_reaching_it) {
    const auto dir = fresh_dir();
    for (const char* solver : {"viscoelastic", "sph"}) {
        SCOPED_TRACE(solver);
        const double until = 0.02;
        const std::string scene = small_scene + "--solver " + solver + " --threads 1 --every 1000 ";
        const auto run = [&](const std::string& args, const std::string& name) {
            const std::string out = name + "_" + solver;
            const tool_result r = run_tool(dir, scene + args + " --out " + out);
            EXPECT_EQ(r.code, 0) << args << ": " << r.err;
            return read_json(dir / out / "summary.json");
        };
        // The scene's dt (viscoelastic) or the CFL's (SPH): any number of steps may be needed.
        const nlohmann::json timed = run("--time 0.02", "timed");
        const auto steps = timed.at("steps").get<std::uint64_t>();
        const double reached = timed.at("simulated_seconds").get<double>();
        EXPECT_GE(reached, until * (1 - 1e-9));
        EXPECT_EQ(timed.at("steps_this_run").get<std::uint64_t>(), steps);
        ASSERT_GE(steps, 2u) << "too few steps to tell";
        // The same number of steps by --steps reaches the same time; one fewer falls short.
        EXPECT_EQ(run("--steps " + std::to_string(steps), "same").at("simulated_seconds").get<double>(), reached);
        EXPECT_LT(run("--steps " + std::to_string(steps - 1), "fewer").at("simulated_seconds").get<double>(),
                  until * (1 - 1e-9) - 1e-12);
    }
    // --time and --steps together: a usage error.
    const tool_result both = run_tool(dir, small_scene + "--steps 3 --time 0.1 --out both");
    EXPECT_EQ(both.code, 2);
    EXPECT_NE(both.err.find("--time"), std::string::npos) << both.err;
}

}  // namespace
}  // namespace frnn::test

#endif  // FRNN_TOOL_HAS_SIM
