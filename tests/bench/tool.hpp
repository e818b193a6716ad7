// Running the built `frnn` from the bench tests (FRNN_TOOL_PATH) and reading what it wrote.
#pragma once
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace frnn::test {

/// Runs `frnn <args>` through the shell (args may redirect); its exit code, or -1.
inline int run(const std::string& args) {
    const std::string cmd = std::string("'") + FRNN_TOOL_PATH + "' " + args;
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// The fields of a CSV line, empty ones (trailing ones too) included.
inline std::vector<std::string> split(const std::string& line, char sep) {
    std::vector<std::string> out;
    std::string item;
    std::istringstream in(line);
    while (std::getline(in, item, sep)) out.push_back(item);
    if (!line.empty() && line.back() == sep) out.emplace_back();
    return out;
}

}  // namespace frnn::test
