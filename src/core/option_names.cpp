// The names of the options' enums, as the CLI, Python and reports spell them.
#include "frnn/error.hpp"
#include "frnn/options.hpp"

#include <string>

namespace frnn {

std::string_view to_string(grid_kind kind) {
    switch (kind) {
        case grid_kind::automatic: return "auto";
        case grid_kind::uniform: return "uniform";
        case grid_kind::hashed: return "hash";
    }
    return "?";
}

grid_kind parse_grid_kind(std::string_view text) {
    if (text == "auto" || text == "automatic") return grid_kind::automatic;
    if (text == "uniform") return grid_kind::uniform;
    if (text == "hash" || text == "hashed") return grid_kind::hashed;
    throw error("unknown grid kind '" + std::string(text) + "' (expected auto, uniform or hash)");
}

std::string_view to_string(radius_rule rule) { return rule == radius_rule::symmetric ? "symmetric" : "gather"; }

radius_rule parse_radius_rule(std::string_view text) {
    if (text == "gather") return radius_rule::gather;
    if (text == "symmetric") return radius_rule::symmetric;
    throw error("unknown radius rule '" + std::string(text) + "' (expected gather or symmetric)");
}

}  // namespace frnn
