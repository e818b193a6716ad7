// The pixel where a point should appear, computed in the tests from the camera's definition
// (eye, target, y up, vertical field of view), independently of the viewer's matrices.
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

/// Perspective projection of p for a camera at `eye` looking at `target` with y up.
inline pixel_xy project(const std::array<double, 3>& p, const std::array<double, 3>& eye, const std::array<double, 3>& target,
                 double fov_degrees, const std::array<int, 4>& viewport, int image_height) {
    using v3 = std::array<double, 3>;
    auto sub = [](const v3& a, const v3& b) { return v3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    auto dot = [](const v3& a, const v3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    auto cross = [](const v3& a, const v3& b) { return v3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; };
    auto unit = [&](const v3& a) {
        const double l = std::sqrt(dot(a, a));
        return v3{a[0] / l, a[1] / l, a[2] / l};
    };
    const v3 f = unit(sub(target, eye)), s = unit(cross(f, {0, 1, 0})), u = cross(s, f), d = sub(p, eye);
    const double t = std::tan(fov_degrees * 3.14159265358979 / 360), aspect = double(viewport[2]) / viewport[3];
    const double nx = dot(d, s) / (dot(d, f) * t * aspect), ny = dot(d, u) / (dot(d, f) * t);
    return {viewport[0] + (nx + 1) / 2 * viewport[2], image_height - (viewport[1] + (ny + 1) / 2 * viewport[3])};
}

}  // namespace frnn::test
