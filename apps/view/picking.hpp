// Picking: the particle under a pixel, by casting the camera's ray through it against every
// particle's sphere (O(N), a few milliseconds at 10^5 particles, once per click).
#pragma once
#include <array>
#include <optional>

#include "camera.hpp"
#include "frnn/sim/simulation.hpp"

namespace frnn::view {

/// The camera's ray through a pixel, and the size of a pixel along it: pixel_at(d) is the
/// width in scene units that one pixel covers at distance d along the ray (orthographic:
/// the same at every distance).
struct pointer_ray {
    vec3f origin, dir;  // dir has unit length
    float pixel0 = 0, pixel1 = 0;
    float pixel_at(float distance) const { return pixel0 + pixel1 * distance; }
    vec3f at(float distance) const { return origin + distance * dir; }
};

/// The ray through pixel (x, y) (from the top-left of the window). viewport: x, y from the
/// bottom, width, height; window_height: the window's height in pixels.
pointer_ray pixel_ray(const camera& cam, const std::array<int, 4>& viewport, int window_height, double x, double y);

/// The id of the nearest particle whose sphere (of `radius`) the ray through pixel (x, y)
/// hits; none when the ray misses them all.
std::optional<std::size_t> pick_particle(const sim::particle_snapshot& s, float radius, const camera& cam,
                                         const std::array<int, 4>& viewport, int window_height, double x, double y);

}  // namespace frnn::view
