// How many cells a grid has and over which box: the rules every backend applies when it plans
// its geometry (the CPU grid's plan in grid_plan.cpp and the Vulkan grid's configure), so that
// both read a domain, size a periodic box, count uniform cells and lay out the cells of their
// grid_geometry alike. The kind choice is kind_policy.hpp. All in search space (see
// frnn/search_scale.hpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "frnn/grid_geometry.hpp"
#include "frnn/options.hpp"

namespace frnn::detail {

/// When the options give a domain, its bounds times `scale` into lo/hi (each first clamped to
/// +-limit, the largest value of the points' type: bounds beyond it hold no more points).
/// Throws frnn::error, its message starting with `who`, when only one bound is given or the
/// bounds are not `dim` finite, ordered values.
void apply_domain(const grid_options& o, int dim, double scale, double limit, double* lo, double* hi,
                  std::string_view who);

/// The cells of a box with periodic axes (search space, dim axes, box[a] > 0 on the periodic
/// ones, 0 on open ones): a uniform grid of at least `cell`-wide cells, box_cells() per axis,
/// from 0 and g.box / dims wide on a periodic axis, from lo and `cell` wide (wider when the box
/// is sparse) on an open one; and its slots. g.box holds the lengths in the points' type.
template <class T>
void lay_out_periodic_cells(grid_geometry<T>& g, const double* box, const double* lo, const double* hi, int dim,
                            double cell, std::size_t n);

/// The cells of an open grid of kind g.kind over [lo, hi] (search space): `cell`-wide cells
/// counted from lo, uniform_cells() of them per axis on a uniform grid; and the slots of the
/// cell index (cells, or a hash table of at least 64 slots and one per point, a power of 2).
template <class T>
void lay_out_open_cells(grid_geometry<T>& g, const double* lo, const double* hi, int dim, double cell,
                        std::size_t n);

/// Cells per axis of a box with periodic axes (box[a] > 0: floor(L / cell)) and open ones
/// (box[a] = 0: over [lo, hi], floor((hi - lo) / cell) + 1), each at least 1 and at most 2^30,
/// then, for sparse boxes, fewer and larger so that the box has at most max(8 n, 4096) cells
/// (still at least `cell` wide, so the reach still holds), taken first from the axes with the
/// most.
std::array<std::int64_t, 3> box_cells(const double* box, const double* lo, const double* hi, int dim, double cell,
                                      std::size_t n);

/// Cells per axis of a uniform grid over [lo, hi]: floor((hi - lo) / cell) + 1; the caller has
/// checked that their product is within its limit.
std::array<std::int64_t, 3> uniform_cells(const double* lo, const double* hi, int dim, double cell);

}  // namespace frnn::detail
