// Runs frnn-view (under xvfb-run, or with no display at all) and the frnn tool from the tests,
// and reads what the viewer leaves: its --state JSON and --screenshot PNG.
#pragma once
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "frnn/sim/output.hpp"
#include "run_command.hpp"
#include "scratch_dir.hpp"

namespace frnn::test {

using run_result = command_result;

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// Runs a shell command in `dir`, collecting exit code, stdout and stderr.
inline run_result run_in(const scratch_dir& dir, const std::string& command) {
    // Leak reports of the sanitizer tree: Mesa's and X's own allocations are not ours.
    return run_command(dir, "LSAN_OPTIONS=suppressions='" FRNN_LSAN_SUPPRESSIONS "' MESA_SHADER_CACHE_DISABLE=true " +
                                command);
}

/// The start of a command run on a virtual screen of its own (a server number per process, so
/// tests run in parallel). The X authority file is kept in the test's folder (-f): the folder
/// xvfb-run makes for it otherwise fails to be removed about one run in 30 (exit code 5).
inline std::string on_virtual_screen() {
    const int server = 100 + int(::getpid() % 800);
    return "'" FRNN_XVFB_RUN "' -a -n " + std::to_string(server) + " -f .xauthority -s '-screen 0 1280x1024x24' ";
}

/// frnn-view with `args` on a virtual screen.
inline run_result run_viewer(const scratch_dir& dir, const std::string& args) {
    return run_in(dir, on_virtual_screen() + "'" FRNN_VIEW_PATH "' --width 960 --height 600 " + args);
}

inline run_result run_tool(const scratch_dir& dir, const std::string& args) {
    return run_in(dir, "'" FRNN_TOOL_PATH "' " + args);
}

inline nlohmann::json read_json(const std::filesystem::path& p) { return nlohmann::json::parse(slurp(p)); }

inline void write_text(const std::filesystem::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
}

/// The number of lines of a message (a trailing newline ends the last one).
inline int lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n + (!s.empty() && s.back() != '\n');
}

using rgb = std::array<int, 3>;
inline rgb pixel(const sim::image& img, int x, int y) {
    const std::size_t k = (std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 3;
    return {img.rgb[k], img.rgb[k + 1], img.rgb[k + 2]};
}
inline int color_distance(const rgb& a, const rgb& b) {
    return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

}  // namespace frnn::test
