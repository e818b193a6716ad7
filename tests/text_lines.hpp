// Picking lines out of a tool's or a table's text in tests.
#pragma once
#include <sstream>
#include <string>

namespace frnn::test {

/// The first line of `text` that starts with `start`, without its newline; "" when none does.
inline std::string line_starting(const std::string& text, const std::string& start) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(start, 0) == 0) return line;
    return "";
}

}  // namespace frnn::test
