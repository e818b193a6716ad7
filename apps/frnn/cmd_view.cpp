// `frnn view ...`: runs the interactive viewer, the frnn-view executable beside this one (in
// the build tree and in an install prefix alike), passing every argument on. Where the viewer
// was not built, one line says which packages it needs and the exit code is 1; the frnn tool
// itself needs no display or OpenGL.
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command.hpp"
#include "frnn/error.hpp"

namespace frnn::app {
namespace {

std::filesystem::path viewer_path() {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) throw error("frnn view: cannot find the frnn executable's folder: " + ec.message());
    return self.parent_path() / "frnn-view";
}

void run_view(const std::vector<std::string>& args) {
    const auto viewer = viewer_path();
    if (::access(viewer.c_str(), X_OK) != 0) throw error("viewer not built (needs libglfw3-dev, libimgui-dev)");
    std::vector<std::string> all{viewer.string()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(viewer.c_str(), argv.data());
    throw error("frnn view: cannot run '" + viewer.string() + "'");
}

const register_command reg{"view", [](CLI::App& app) {
    auto* c = app.add_subcommand("view", "Run a particle-fluid scene live in a window (the frnn-view program; "
                                         "frnn view --help lists its options)");
    c->prefix_command();  // every argument goes to frnn-view
    c->set_help_flag();   // --help too
    c->callback([c] { run_view(c->remaining()); });
}};

}  // namespace
}  // namespace frnn::app
