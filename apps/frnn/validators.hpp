// Option checks of the frnn tool with short messages (CLI11's range checks print the whole
// double range).
#pragma once
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace frnn::app {

/// A finite number > 0.
inline const CLI::Validator positive_number{
    [](std::string& text) -> std::string {
        try {
            std::size_t used = 0;
            const double v = std::stod(text, &used);
            if (used == text.size() && std::isfinite(v) && v > 0) return {};
        } catch (const std::exception&) {
        }
        return "must be a finite number > 0 (got '" + text + "')";
    },
    "POSITIVE"};

}  // namespace frnn::app
