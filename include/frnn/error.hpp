// frnn::error: the one exception type frnn throws for bad input and failures.
// Messages say what was wrong and where (file, line, point index, option name).
#pragma once
#include <stdexcept>
#include <string>

namespace frnn {

/// Thrown for invalid arguments (non-finite coordinates, radius <= 0, ...) and failures.
class error : public std::runtime_error {
public:
    explicit error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace frnn
