// The frnn command-line tool. Exit codes: 0 success, 1 bad input or failure, 2 usage error,
// others as a command says (frnn::app::exit_status).
#include <algorithm>
#include <cstdio>
#include <exception>

#include "command.hpp"

namespace frnn::app {
std::vector<command>& commands() {
    static std::vector<command> all;
    return all;
}
}  // namespace frnn::app

int main(int argc, char** argv) {
    CLI::App app{"frnn: fast fixed-radius neighbor search of particles"};
    app.set_version_flag("--version", "frnn " FRNN_VERSION);
    app.require_subcommand(1);
    auto& cmds = frnn::app::commands();
    std::sort(cmds.begin(), cmds.end(), [](auto& a, auto& b) { return a.name < b.name; });
    for (auto& c : cmds) c.setup(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const frnn::app::exit_status& e) {
        if (!e.message.empty()) std::fprintf(stderr, "frnn: %s\n", e.message.c_str());
        return e.code;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "frnn: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "frnn: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
