// Line segments outlining the scene at time t: the domain box, planes as bounded squares,
// spheres as three great circles (one in 2D), boxes by their edges (a rectangle in 2D).
#pragma once
#include <array>
#include <vector>

#include "frnn/sim/scene.hpp"

namespace frnn::view {

struct line_vertex {
    float x, y, z, r, g, b;
};

/// Pairs of vertices, one pair per segment.
std::vector<line_vertex> scene_lines(const sim::scene& s, double t);

/// Appends the outline of one collider (a plane: a square `size` wide; flat: in the xy plane).
void collider_lines(std::vector<line_vertex>& out, const sim::posed_collider& p, bool flat, double size,
                    const std::array<float, 3>& color);
/// The length of the domain's diagonal (in the xy plane for a 2D scene).
double scene_size(const sim::scene& s);

}  // namespace frnn::view
