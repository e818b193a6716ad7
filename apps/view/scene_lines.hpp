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

}  // namespace frnn::view
