// The automatic choice of grid kind, one policy for every backend (the CPU grid's plan and the
// Vulkan grid's configure call it): a uniform grid when its box needs few enough cells for N,
// else a uniform grid over the bulk of the points with far outliers folded into its border
// cells, else the hashed grid.
#pragma once
#include <cstddef>
#include <span>

#include "frnn/options.hpp"

namespace frnn::detail {

/// What the choice looks at, in search space (see frnn/search_scale.hpp).
struct kind_question {
    grid_kind asked = grid_kind::automatic;
    std::size_t n = 0;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  ///< the points' bounding box, or the domain
    bool explicit_domain = false;                 ///< lo/hi are the caller's domain: kept
    double cell = 1, radius = 1;
    /// The farthest cell coordinate the backend's hashed grid keys (infinity: it has no limit);
    /// points beyond it are folded into a uniform grid over the bulk, however many.
    double hashed_key_limit = 0;
    /// The most cells a uniform grid of the backend may have.
    double uniform_cell_limit = 0;
};

/// The answer: the kind (never automatic) and, for a uniform grid, its box and cell count.
struct kind_answer {
    grid_kind kind = grid_kind::uniform;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    double cells = 0;
};

/// The choice for points `coords` (N*D interleaved, search space). `coords` may be empty when
/// the points are not at hand (a device buffer): then no bulk box is tried. `asked` other than
/// automatic is kept; the caller checks a uniform grid against its cell limit.
template <class T, int D>
kind_answer choose_kind(const kind_question& q, std::span<const T> coords, int threads);

}  // namespace frnn::detail
