// Colliders by hand, the geometry of it: which collider is under the pointer, where a drag
// puts it, a turn about the view direction, and the sphere or box the panel adds. No OpenGL and
// no window: the viewer calls these with the camera's ray (picking.hpp).
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "frnn/sim/scene.hpp"
#include "picking.hpp"
#include "scene_lines.hpp"

namespace frnn::view {

/// The turn of one press of `[` (counterclockwise as seen) or `]` (clockwise), in degrees.
inline constexpr double rotate_step_degrees = 15;

/// How near, in pixels, the pointer must come to a collider's outline to pick it.
inline constexpr float outline_pick_pixels = 5;

/// The index of the nearest collider of `s` (posed at time t) under the ray: an obstacle sphere
/// or box where the ray meets its solid, any collider (containers and planes too) where the
/// ray passes within outline_pick_pixels of its drawn outline (scene_lines.hpp). None if
/// nothing is there.
std::optional<std::size_t> pick_collider(const sim::scene& s, double t, const pointer_ray& ray);

/// The outline of collider `selected` of `s` at time t, highlighted; empty when none.
std::vector<line_vertex> selection_outline(const sim::scene& s, double t, std::optional<std::size_t> selected);

/// Where the ray meets the plane through `point` with normal `normal`; none when it runs
/// parallel to it.
std::optional<sim::vec3> on_plane(const pointer_ray& ray, const sim::vec3& point, const vec3f& normal);

/// `c` turned by `radians` about `axis` (unit length, through its center), right-handed: the
/// new orientation is the turn applied after the collider's own (axis, angle).
sim::collider turned(sim::collider c, const sim::vec3& axis, double radians);

/// The point nearest `at` that has no particle (x: 3 floats each) within `clearance` and lies
/// `reach` or more inside the domain on every axis (z = 0 in 2D); `at` when there is none.
/// O(particles + domain volume / clearance^3).
sim::vec3 free_spot(const sim::scene& s, const std::vector<float>& x, const sim::vec3& at, double reach, double clearance);

/// A new obstacle of `kind` (sphere or box), its radius (half side) r a tenth of the domain's
/// smallest side, at the free spot nearest `at` with a particle spacing of room around it
/// (dropped into the fluid it would throw the particles inside it to its surface in one step,
/// which the solvers seldom survive); named "<kind> N" with N free in `s`; flattened in 2D.
sim::collider new_collider(sim::shape kind, const sim::scene& s, const sim::vec3& at, const std::vector<float>& particles,
                           double spacing);

}  // namespace frnn::view
