#include "camera.hpp"

#include <algorithm>
#include <cmath>

namespace frnn::view {
namespace {
constexpr float radians_per_degree = 3.14159265358979f / 180;
}

void camera::frame(const vec3f& lo, const vec3f& hi, bool plane_view) {
    plane_ = plane_view;
    home_target_ = 0.5f * (lo + hi);
    if (plane_) home_target_[2] = 0;
    const vec3f d = hi - lo;
    scene_size_ = std::sqrt(plane_ ? d[0] * d[0] + d[1] * d[1] : dot(d, d));
    // Far enough that the bounding sphere fits in the vertical field of view, with a margin.
    home_distance_ = 0.5f * scene_size_ / std::sin(0.5f * fov_ * radians_per_degree) * 1.05f;
    home_half_height_ = 0.55f * std::max(d[1], d[0] * 0.6f);
    reset();
}

void camera::reset() {
    target_ = home_target_;
    distance_ = home_distance_;
    half_height_ = home_half_height_;
    yaw_ = 30;
    pitch_ = 20;
}

void camera::orbit(float dx, float dy) {
    if (plane_) return;  // a 2D scene stays in its plane
    yaw_ -= 0.3f * dx;
    pitch_ = std::clamp(pitch_ + 0.3f * dy, -89.f, 89.f);
}

void camera::pan(float dx, float dy, int viewport_height) {
    // Move the target by the pixels' size at the target's depth, so it follows the mouse.
    const float units_per_pixel = plane_ ? 2 * half_height_ / float(viewport_height)
                                         : 2 * distance_ * std::tan(0.5f * fov_ * radians_per_degree) / float(viewport_height);
    const mat4 v = view();
    const vec3f right{v[0], v[4], v[8]}, up_dir{v[1], v[5], v[9]};
    target_ = target_ - (units_per_pixel * dx) * right + (units_per_pixel * dy) * up_dir;
}

void camera::zoom(float steps) {
    const float f = std::pow(0.9f, steps);
    distance_ = std::clamp(distance_ * f, 1e-3f * scene_size_, 100 * scene_size_);
    half_height_ = std::clamp(half_height_ * f, 1e-3f * scene_size_, 100 * scene_size_);
}

void camera::set_orbit(const vec3f& target, float distance, float yaw, float pitch, float fov) {
    target_ = target;
    distance_ = distance;
    yaw_ = yaw;
    pitch_ = std::clamp(pitch, -89.f, 89.f);
    fov_ = fov;
}

vec3f camera::eye() const {
    if (plane_) return {target_[0], target_[1], target_[2] + std::max(1.f, scene_size_)};
    const float y = yaw_ * radians_per_degree, p = pitch_ * radians_per_degree;
    return target_ + distance_ * vec3f{std::cos(p) * std::sin(y), std::sin(p), std::cos(p) * std::cos(y)};
}

mat4 camera::view() const { return look_at(eye(), target_, up()); }

mat4 camera::projection(float aspect) const {
    if (plane_) {
        const float h = half_height_, depth = std::max(1.f, scene_size_);
        return orthographic(-h * aspect, h * aspect, -h, h, 0.f, 2 * depth);
    }
    const float near = std::max(0.01f * distance_, distance_ - scene_size_), far = distance_ + 2 * scene_size_;
    return perspective(fov_ * radians_per_degree, aspect, near * 0.5f, far);
}

}  // namespace frnn::view
