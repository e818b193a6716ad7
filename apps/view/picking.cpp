#include "picking.hpp"

#include <cmath>
#include <limits>

namespace frnn::view {

pointer_ray pixel_ray(const camera& cam, const std::array<int, 4>& viewport, int window_height, double x, double y) {
    // The pixel in normalized device coordinates of the scene's viewport.
    const float nx = float(2 * (x - viewport[0]) / viewport[2] - 1);
    const float ny = float(2 * ((window_height - y) - viewport[1]) / viewport[3] - 1);
    const float aspect = float(viewport[2]) / float(viewport[3]);
    const vec3f eye = cam.eye(), forward = normalize(cam.target() - eye);
    const vec3f right = normalize(cross(forward, cam.up())), up = cross(right, forward);
    pointer_ray r{eye, forward};
    if (cam.plane_view()) {  // orthographic: parallel rays
        const float h = cam.half_height();
        r.origin = eye + (nx * h * aspect) * right + (ny * h) * up;
        r.pixel0 = 2 * h / float(viewport[3]);
    } else {
        const float t = std::tan(0.5f * cam.fov_degrees() * 3.14159265358979f / 180);
        r.dir = normalize(forward + (nx * t * aspect) * right + (ny * t) * up);
        r.pixel1 = 2 * t / float(viewport[3]);
    }
    return r;
}

std::optional<std::size_t> pick_particle(const sim::particle_snapshot& s, float radius, const camera& cam,
                                         const std::array<int, 4>& viewport, int window_height, double x, double y) {
    const pointer_ray ray = pixel_ray(cam, viewport, window_height, x, y);
    float best = std::numeric_limits<float>::infinity();
    std::optional<std::size_t> hit;
    for (std::size_t k = 0; k < s.n; ++k) {
        const vec3f c{s.x[k * 3], s.x[k * 3 + 1], s.x[k * 3 + 2]};
        const vec3f oc = c - ray.origin;
        const float along = dot(oc, ray.dir), d2 = dot(oc, oc) - along * along;
        if (d2 > radius * radius) continue;
        const float entry = along - std::sqrt(radius * radius - d2);  // where the ray enters the sphere
        if (entry > 0 && entry < best) best = entry, hit = k;
    }
    return hit;
}

}  // namespace frnn::view
