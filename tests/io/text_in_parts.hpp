// A text point file parsed whole and in parts, as the ranks of a distributed query read it
// (frnn/io/read.hpp): shared by the reader's tests and the point-file fuzzer, which compare the
// two.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/io/read.hpp"

namespace frnn::test {

/// Points read from text, or (without points) the error that stopped the read.
struct text_result {
    std::vector<double> coords;
    int dimension = 0;
    std::string error;
};

inline text_result read_text_whole(std::string_view text) {
    text_result r;
    try {
        io::point_set p = io::parse_text_points(text, "p.csv");
        r.coords = std::get<std::vector<double>>(p.coords);
        r.dimension = p.dimension;
    } catch (const error& e) {
        r.error = e.what();
    }
    return r;
}

/// The parts of `text` read apart and joined: the error is the first failing part's, and the
/// dimension that of the whole file's first data line. A part whose first point number is not
/// the count of the points before it is an error too.
inline text_result read_text_in_parts(std::string_view text, std::uint64_t parts) {
    std::vector<io::text_part_summary> summaries;
    for (std::uint64_t k = 0; k < parts; ++k) summaries.push_back(io::summarize_text_part(io::text_part(text, k, parts)));
    const io::text_context all = io::context_after(summaries);
    text_result r;
    r.dimension = all.columns == 0 ? 3 : int(all.columns);
    for (std::uint64_t k = 0; k < parts; ++k) {
        const io::text_context before = io::context_after(std::span(summaries).first(k));
        try {
            const io::point_set p = io::parse_text_part(io::text_part(text, k, parts), "p.csv", before);
            const auto& coords = std::get<std::vector<double>>(p.coords);
            if (before.points * std::uint64_t(r.dimension) != r.coords.size())
                return {{}, 0, "part " + std::to_string(k) + " starts at point " + std::to_string(before.points)};
            r.coords.insert(r.coords.end(), coords.begin(), coords.end());
        } catch (const error& e) {
            return {{}, 0, e.what()};
        }
    }
    if (all.points * std::uint64_t(r.dimension) != r.coords.size())
        return {{}, 0, "the parts count " + std::to_string(all.points) + " points"};
    return r;
}

}  // namespace frnn::test
