// Subcommand registry of the frnn tool: each cmd_*.cpp registers itself with one
// static register_command, so adding a subcommand never edits main.cpp.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace frnn::app {

/// Adds the subcommand (with its options and callback) to the tool's parser.
using command_setup = std::function<void(CLI::App& app)>;

struct command {
    std::string name;
    command_setup setup;
};

std::vector<command>& commands();

/// Thrown by a command to end the tool with `code`: for outcomes that are neither success (0)
/// nor an error main should print (such as `frnn validate`'s 3), and for errors the command
/// has printed itself (once for all MPI ranks). main prints `message` when it is not empty.
struct exit_status {
    int code = 1;
    std::string message;
};

struct register_command {
    register_command(std::string name, command_setup setup) {
        commands().push_back({std::move(name), std::move(setup)});
    }
};

}  // namespace frnn::app
