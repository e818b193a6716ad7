// The pixel where a point should appear, computed in the tests from the camera's definition
// (eye, target, y up, vertical field of view), independently of the viewer's matrices, and
// back from a pixel to the point at a given depth.
#pragma once
#include <array>
#include <cmath>

namespace frnn::test {

struct pixel_xy {
    double x, y;  // from the image's top-left
};

/// The eye of the scripts' orbit camera: `distance` from `target`, turned `yaw` degrees about
/// y from +z and raised `pitch` degrees (docs/VIEWER.md, action "camera").
inline std::array<double, 3> orbit_eye(const std::array<double, 3>& target, double distance, double yaw, double pitch) {
    const double pi = 3.14159265358979, y = yaw * pi / 180, p = pitch * pi / 180;
    return {target[0] + distance * std::cos(p) * std::sin(y), target[1] + distance * std::sin(p),
            target[2] + distance * std::cos(p) * std::cos(y)};
}

namespace projection_detail {
using v3 = std::array<double, 3>;
inline v3 sub(const v3& a, const v3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const v3& a, const v3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline v3 cross(const v3& a, const v3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
inline v3 unit(const v3& a) {
    const double l = std::sqrt(dot(a, a));
    return {a[0] / l, a[1] / l, a[2] / l};
}
/// The camera's forward, right and up directions, and tan(fov / 2).
struct basis {
    v3 f, s, u;
    double t;
    basis(const v3& eye, const v3& target, double fov_degrees)
        : f(unit(sub(target, eye))), s(unit(cross(f, {0, 1, 0}))), u(cross(s, f)), t(std::tan(fov_degrees * 3.14159265358979 / 360)) {}
};
}  // namespace projection_detail

/// Perspective projection of p for a camera at `eye` looking at `target` with y up.
inline pixel_xy project(const std::array<double, 3>& p, const std::array<double, 3>& eye, const std::array<double, 3>& target,
                 double fov_degrees, const std::array<int, 4>& viewport, int image_height) {
    using namespace projection_detail;
    const basis b(eye, target, fov_degrees);
    const v3 d = sub(p, eye);
    const double aspect = double(viewport[2]) / viewport[3];
    const double nx = dot(d, b.s) / (dot(d, b.f) * b.t * aspect), ny = dot(d, b.u) / (dot(d, b.f) * b.t);
    return {viewport[0] + (nx + 1) / 2 * viewport[2], image_height - (viewport[1] + (ny + 1) / 2 * viewport[3])};
}

/// The inverse of project() for the points at the depth of `on`: where the ray from the eye
/// through pixel `at` meets the plane through `on` facing the camera (perpendicular to the
/// direction from eye to target).
inline std::array<double, 3> unproject(const pixel_xy& at, const std::array<double, 3>& on, const std::array<double, 3>& eye,
                                       const std::array<double, 3>& target, double fov_degrees, const std::array<int, 4>& viewport,
                                       int image_height) {
    using namespace projection_detail;
    const basis b(eye, target, fov_degrees);
    const double aspect = double(viewport[2]) / viewport[3];
    const double nx = 2 * (at.x - viewport[0]) / viewport[2] - 1, ny = 2 * ((image_height - at.y) - viewport[1]) / viewport[3] - 1;
    // The ray's direction scaled to advance 1 along f; the plane is depth dot(on - eye, f) away.
    const double depth = dot(sub(on, eye), b.f);
    v3 p{};
    for (int a = 0; a < 3; ++a) p[a] = eye[a] + depth * (b.f[a] + nx * b.t * aspect * b.s[a] + ny * b.t * b.u[a]);
    return p;
}

}  // namespace frnn::test
