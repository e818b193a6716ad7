// The search made visible: for a picked particle, the grid cells its fixed-radius search visits
// and the neighbors it finds there, from the geometry of the grid the solver's last step built
// (frnn::grid_geometry, carried by the snapshot). The simulation's grid is bounded, never
// periodic (a fixed domain padded by the radius), so plain distances are the search's.
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "frnn/sim/simulation.hpp"
#include "scene_lines.hpp"

namespace frnn::view {

struct particle_search {
    /// The cells of cells_within(x) whose box lies within the radius of x: the only ones the
    /// search can find neighbors in (the others of the block it visits are outlined by the
    /// cell grid toggle).
    std::vector<cell_index> cells;
    /// The particles j != id with |x_j - x_id| <= radius, found in those cells, in id order.
    std::vector<std::size_t> neighbors;
};

/// The search of particle `id` in `s` (empty before the first step, when there is no grid).
particle_search search_of(const sim::particle_snapshot& s, std::size_t id);

/// Every cell of cells_within(p): the block a query at p (caller's units) visits.
std::vector<cell_index> visited_cells(const sim::particle_snapshot& s, const std::array<float, 3>& p);

/// The cells' boxes (cell_bounds) as line segments of one color, rectangles in 2D.
std::vector<line_vertex> cell_lines(const sim::particle_snapshot& s, const std::vector<cell_index>& cells,
                                    const std::array<float, 3>& color);

}  // namespace frnn::view
