// The few 3-vector and 4x4-matrix operations the viewer draws with: column-major matrices as
// OpenGL takes them, the classic look-at, perspective and orthographic projections.
#pragma once
#include <array>
#include <cmath>

namespace frnn::view {

using vec3f = std::array<float, 3>;
using mat4 = std::array<float, 16>;  // column-major: element (row r, column c) at c * 4 + r

inline vec3f operator-(const vec3f& a, const vec3f& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline vec3f operator+(const vec3f& a, const vec3f& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline vec3f operator*(float s, const vec3f& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline float dot(const vec3f& a, const vec3f& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline vec3f cross(const vec3f& a, const vec3f& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline vec3f normalize(const vec3f& a) {
    const float l = std::sqrt(dot(a, a));
    return l > 0 ? (1 / l) * a : a;
}

inline mat4 multiply(const mat4& a, const mat4& b) {
    mat4 m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            float s = 0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
            m[c * 4 + r] = s;
        }
    return m;
}

inline mat4 look_at(const vec3f& eye, const vec3f& target, const vec3f& up) {
    const vec3f f = normalize(target - eye), s = normalize(cross(f, up)), u = cross(s, f);
    return {s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1};
}

inline mat4 perspective(float fov_y_radians, float aspect, float near, float far) {
    const float t = 1 / std::tan(fov_y_radians / 2);
    return {t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (far + near) / (near - far), -1, 0, 0, 2 * far * near / (near - far), 0};
}

inline mat4 orthographic(float left, float right, float bottom, float top, float near, float far) {
    return {2 / (right - left), 0, 0, 0, 0, 2 / (top - bottom), 0, 0, 0, 0, -2 / (far - near), 0,
            -(right + left) / (right - left), -(top + bottom) / (top - bottom), -(far + near) / (far - near), 1};
}

}  // namespace frnn::view
