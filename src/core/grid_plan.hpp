// The choice of a grid's geometry, made in full before a build changes anything, so that a
// build whose input is invalid throws and leaves the grid as it was.
#pragma once
#include <span>
#include <vector>

#include "frnn/buffer.hpp"
#include "frnn/grid_geometry.hpp"
#include "frnn/options.hpp"

namespace frnn::detail {

/// Validates a build's input (radius, coordinates, cell size, box, domain) and chooses the
/// geometry of a grid<T, D> over `coords`: search scale, kind, cell size, reach, cells per axis
/// or table slots. Changes nothing but `search_input`, a build's scratch: the coordinates in
/// search space (wrapped into a periodic box, then scaled) when they differ from the caller's,
/// else empty. Throws frnn::error naming what is wrong and where.
template <class T, int D>
grid_geometry<T> plan_geometry(std::span<const T> coords, T radius, const grid_options& options,
                               buffer<T>& search_input);

}  // namespace frnn::detail
