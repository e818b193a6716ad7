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

namespace {
// An error before any rank talks to another is the same on every rank (the same arguments):
// under a launcher of several ranks rank 0 alone prints it and fails, and the others end
// quietly with 0, since a rank failing first could let the launcher end rank 0 before its
// message is out.
int report(const std::string& message, int code) {
    if (frnn::app::launcher_ranks() > 1 && frnn::app::launcher_rank() != 0) return 0;
    if (!message.empty()) std::fprintf(stderr, "%s\n", message.c_str());
    std::fflush(stderr);
    return code;
}
}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"frnn: fast fixed-radius neighbor search of particles"};
    app.set_version_flag("--version", "frnn " FRNN_VERSION);
    app.require_subcommand(1);
    auto& cmds = frnn::app::commands();
    std::sort(cmds.begin(), cmds.end(), [](auto& a, auto& b) { return a.name < b.name; });
    for (auto& c : cmds) c.setup(app);
    // Only `frnn query` and `frnn sim` (with MPI) run across ranks: any other command under a
    // launcher of several ranks would run one independent copy per rank (the same outputs
    // written over each other).
    const std::string command = argc > 1 ? argv[1] : "";
#if defined(FRNN_MPI_AVAILABLE) && defined(FRNN_SIM_AVAILABLE)
    const bool across_ranks = command == "query" || command == "sim";
    const char* which = "only `frnn query` and `frnn sim` run across ranks";
#else
    const bool across_ranks = command == "query";
    const char* which = "only `frnn query` runs across ranks";
#endif
    if (!across_ranks && command.rfind("-", 0) != 0 && frnn::app::launcher_ranks() > 1)
        return report("frnn: " + command + " runs in one process, but an MPI launcher started " +
                          std::to_string(frnn::app::launcher_ranks()) +
                          " ranks (each would run its own copy): run it without mpirun; " + which,
                      1);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const frnn::app::exit_status& e) {
        return report(e.message.empty() ? "" : "frnn: " + e.message, e.code);
    } catch (const CLI::ParseError& e) {
        return report(std::string("frnn: ") + e.what(), 2);
    } catch (const std::exception& e) {
        return report(std::string("frnn: error: ") + e.what(), 1);
    }
    return 0;
}
