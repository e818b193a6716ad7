// The frnn command-line tool. Exit codes: 0 success, 1 bad input or failure, 2 usage error,
// others as a command says (frnn::app::exit_status).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "command.hpp"
#include "launcher.hpp"

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
    // Only `frnn query` runs across ranks: any other command under a launcher of several ranks
    // would run one independent copy per rank (the same outputs written over each other).
    const std::string command = argc > 1 ? argv[1] : "";
    // Rank 0 prints the message and fails the job; the other ranks end quietly with 0, since a
    // rank that failed first would let the launcher kill rank 0 before its message is out.
    if (command != "query" && command.rfind("-", 0) != 0 && frnn::app::launcher_ranks() > 1) {
        if (frnn::app::launcher_rank() != 0) return 0;
        std::fprintf(stderr,
                     "frnn: %s runs in one process, but an MPI launcher started %ld ranks (each would run its own "
                     "copy): run it without mpirun; only `frnn query` runs across ranks\n",
                     command.c_str(), frnn::app::launcher_ranks());
        std::fflush(stderr);
        return 1;
    }
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
