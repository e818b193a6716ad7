// Fuzzing the scene parser and writer: any text gives a scene or frnn::error; a scene that
// parses is written back as JSON that parses again to the same JSON; and a small version of
// it (at most 64 particles, two steps) runs or stops with frnn::error.
#include <cstdint>
#include <cstdio>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/simulation.hpp"
#include "fuzz_input.hpp"

namespace frnn::fuzz {
namespace {

void run(std::string_view text) {
    sim::scene s;
    try {
        s = sim::parse_scene(std::string(text), "fuzz.json");
    } catch (const error&) {
        return;
    }
    reached_checks();
    const std::string json = sim::scene_to_json(s);
    sim::scene again;
    try {
        again = sim::parse_scene(json, "written.json");
    } catch (const error&) {
        fail("a parsed scene, written back, does not parse");
    }
    const std::string json_again = sim::scene_to_json(again);
    if (json_again != json) {
        std::fprintf(stderr, "written:\n%s\nread back and written again:\n%s\n", json.c_str(), json_again.c_str());
        fail("a written scene reads back to another scene");
    }

    sim::scene_overrides small;
    small.particles = 64;
    try {
        sim::apply(s, small);
        sim::simulation run(s, 1);
        run.step();
        run.step();
    } catch (const error&) {
    }
}

}  // namespace
}  // namespace frnn::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    frnn::fuzz::run(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
