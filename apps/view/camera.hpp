// The viewer's camera: in 3D an orbit around a target (yaw, pitch, distance) with a
// perspective projection; in 2D a plane view of the xy plane with an orthographic projection.
// Mouse: left drag orbits (3D), right or middle drag pans, the wheel zooms. Thread safety: none.
#pragma once
#include "linear_algebra.hpp"

namespace frnn::view {

class camera {
public:
    /// Frames the box [lo, hi] (z ignored in 2D) and remembers that framing for reset().
    void frame(const vec3f& lo, const vec3f& hi, bool plane_view);
    void reset();

    void orbit(float dx_pixels, float dy_pixels);
    void pan(float dx_pixels, float dy_pixels, int viewport_height);
    void zoom(float wheel_steps);

    /// Sets the orbit explicitly (degrees), for scripts and tests.
    void set_orbit(const vec3f& target, float distance, float yaw_degrees, float pitch_degrees, float fov_degrees);

    mat4 view() const;
    mat4 projection(float aspect) const;
    vec3f eye() const;
    vec3f up() const { return {0, 1, 0}; }
    const vec3f& target() const { return target_; }
    float fov_degrees() const { return fov_; }
    bool plane_view() const { return plane_; }
    /// Half the visible height of the plane view, in scene units.
    float half_height() const { return half_height_; }

private:
    bool plane_ = false;
    vec3f target_{0, 0, 0};
    float distance_ = 3, yaw_ = 30, pitch_ = 20, fov_ = 45, half_height_ = 1, scene_size_ = 1;
    vec3f home_target_{0, 0, 0};
    float home_distance_ = 3, home_half_height_ = 1;
};

}  // namespace frnn::view
