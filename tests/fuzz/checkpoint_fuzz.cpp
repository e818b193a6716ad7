// Fuzzing checkpoint loading: any bytes as a checkpoint.bin load into a simulation or give
// frnn::error, never a crash or memory beyond the file's; a loaded simulation steps twice and
// takes a snapshot, or stops with frnn::error. Checkpoints whose scene seeds more than 4096
// particles are skipped (seeding them is the scene's cost, not the file's).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "checkpoint.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/simulation.hpp"
#include "fuzz_input.hpp"

namespace frnn::fuzz {
namespace {

bool small_enough(const std::string& bytes) {
    try {
        std::istringstream in(bytes, std::ios::binary);
        const sim::detail::checkpoint_header h = sim::detail::read_checkpoint_header(in, "fuzz");
        sim::scene s = sim::parse_scene(h.scene_json, h.origin);
        sim::apply(s, h.ov);
        return s.target_particles() <= 4096;
    } catch (const error&) {
        return true;  // load_checkpoint meets the same error first
    }
}

void run(const std::string& bytes) {
    if (!small_enough(bytes)) return;
    static const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("frnn-fuzz-" + std::to_string(::getpid()) + ".bin");
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    sim::scene_overrides small;
    small.particles = 64;
    sim::scene s = sim::builtin_scene("dam-break");
    sim::apply(s, small);
    sim::simulation run(s, 1);
    bool loaded = false;
    try {
        run.load_checkpoint(file.string());
        loaded = true;
    } catch (const error&) {
    }
    std::filesystem::remove(file);  // before the steps: a finding stops the process
    if (!loaded) return;
    reached_checks();
    try {
        run.step();
        run.step();
        sim::particle_snapshot snap;
        run.snapshot(snap);
    } catch (const error&) {
    }
}

}  // namespace
}  // namespace frnn::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    frnn::fuzz::run(std::string(reinterpret_cast<const char*>(data), size));
    return 0;
}
