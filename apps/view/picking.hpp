// Picking: the particle under a pixel, by casting the camera's ray through it against every
// particle's sphere (O(N), a few milliseconds at 10^5 particles, once per click).
#pragma once
#include <array>
#include <optional>

#include "camera.hpp"
#include "frnn/sim/simulation.hpp"

namespace frnn::view {

/// The id of the nearest particle whose sphere (of `radius`) the ray through pixel (x, y)
/// (from the top-left of the window) hits; none when the ray misses them all. viewport: x, y
/// from the bottom, width, height; window_height: the window's height in pixels.
std::optional<std::size_t> pick_particle(const sim::particle_snapshot& s, float radius, const camera& cam,
                                         const std::array<int, 4>& viewport, int window_height, double x, double y);

}  // namespace frnn::view
