// Runs a shell command in a folder and collects its exit code, stdout and stderr: the tests of
// the frnn tool (cli/) and of the viewer (viewer/) start the built programs with it.
#pragma once
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace frnn::test {

struct command_result {
    int code = -1;  ///< the exit code; -1 when the command did not exit normally
    std::string out, err;
};

/// Runs `command` (shell syntax, quoted by the caller) with `dir` as its working folder. Its
/// output goes through two files in `dir`, removed before this returns.
inline command_result run_command(const std::filesystem::path& dir, const std::string& command) {
    const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
    const std::string full = "cd '" + dir.string() + "' && " + command + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(full.c_str());
    auto read = [](const std::filesystem::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    command_result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read(out);
    r.err = read(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

}  // namespace frnn::test
