// Signed distance functions of the colliders and the projection of particles out of them.
#include "frnn/sim/colliders.hpp"

#include <algorithm>
#include <cmath>

namespace frnn::sim {
namespace {
constexpr double pi = 3.14159265358979323846;

double dot(const vec3& a, const vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
vec3 cross(const vec3& a, const vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
vec3 normalized(vec3 a) {
    const double l = std::sqrt(dot(a, a));
    if (l > 0)
        for (double& c : a) c /= l;
    return a;
}
}  // namespace

posed_collider::posed_collider(const collider& c, double t) : c_(&c) {
    const motion& m = c.path;
    const double w = 2 * pi * m.frequency;
    for (int a = 0; a < 3; ++a) {
        center_[a] = c.center[a] + m.velocity[a] * t + m.amplitude[a] * std::sin(w * t + m.phase);
        lin_vel_[a] = m.velocity[a] + m.amplitude[a] * w * std::cos(w * t + m.phase);
    }
    const vec3 k = normalized(c.axis);
    for (int a = 0; a < 3; ++a) omega_[a] = k[a] * m.angular_velocity;
    // Rodrigues: R = I cos + (1 - cos) k k^T + sin [k]x.
    const double th = c.angle + m.angular_velocity * t, co = std::cos(th), si = std::sin(th);
    const double kx[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rot_[i][j] = (i == j ? co : 0) + (1 - co) * k[i] * k[j] + si * kx[i][j];
    normal_ = to_world_dir(normalized(c.normal));
}

vec3 posed_collider::to_local(const vec3& x) const {
    vec3 d{x[0] - center_[0], x[1] - center_[1], x[2] - center_[2]}, r{};
    for (int i = 0; i < 3; ++i) r[i] = rot_[0][i] * d[0] + rot_[1][i] * d[1] + rot_[2][i] * d[2];
    return r;
}

vec3 posed_collider::to_world_dir(const vec3& d) const {
    vec3 r{};
    for (int i = 0; i < 3; ++i) r[i] = rot_[i][0] * d[0] + rot_[i][1] * d[1] + rot_[i][2] * d[2];
    return r;
}

double posed_collider::phi(const vec3& x, vec3& n) const {
    double sdf = 0;  // distance from the solid, positive outside the shape
    switch (c_->kind) {
        case shape::plane: {
            n = normal_;
            return dot(vec3{x[0] - center_[0], x[1] - center_[1], x[2] - center_[2]}, normal_);
        }
        case shape::sphere: {
            vec3 d{x[0] - center_[0], x[1] - center_[1], x[2] - center_[2]};
            const double l = std::sqrt(dot(d, d));
            n = l > 0 ? vec3{d[0] / l, d[1] / l, d[2] / l} : vec3{0, 1, 0};
            sdf = l - c_->radius;
            break;
        }
        case shape::box: {
            const vec3 p = to_local(x);
            vec3 q, out{0, 0, 0};
            double outside2 = 0;
            int far_axis = 0;
            for (int a = 0; a < 3; ++a) {
                q[a] = std::abs(p[a]) - c_->half[a];
                if (q[a] > 0) {
                    out[a] = p[a] < 0 ? -q[a] : q[a];
                    outside2 += q[a] * q[a];
                }
                if (q[a] > q[far_axis]) far_axis = a;
            }
            vec3 local{0, 0, 0};
            if (outside2 > 0) {
                sdf = std::sqrt(outside2);
                local = {out[0] / sdf, out[1] / sdf, out[2] / sdf};
            } else {
                sdf = q[far_axis];
                local[far_axis] = p[far_axis] < 0 ? -1 : 1;
            }
            n = to_world_dir(local);
            break;
        }
    }
    if (c_->inside) {
        for (double& c : n) c = -c;
        return -sdf;
    }
    return sdf;
}

vec3 posed_collider::velocity_at(const vec3& x) const {
    const vec3 r{x[0] - center_[0], x[1] - center_[1], x[2] - center_[2]};
    const vec3 w = cross(omega_, r);
    return {lin_vel_[0] + w[0], lin_vel_[1] + w[1], lin_vel_[2] + w[2]};
}

bool posed_collider::resolve(vec3& x, vec3& v, double margin) const {
    vec3 n;
    vec3 target = x;
    if (c_->kind == shape::box && c_->inside) {
        // Exact projection into the box shrunk by the margin: clamp in the box's frame.
        const vec3 p = to_local(x);
        vec3 c = p;
        bool moved = false;
        for (int a = 0; a < 3; ++a) {
            const double lim = std::max(0.0, c_->half[a] - margin);
            if (c[a] > lim) c[a] = lim, moved = true;
            if (c[a] < -lim) c[a] = -lim, moved = true;
        }
        if (!moved) return false;
        const vec3 d = to_world_dir(vec3{c[0] - p[0], c[1] - p[1], c[2] - p[2]});
        for (int a = 0; a < 3; ++a) target[a] = x[a] + d[a];
        n = normalized(d);
    } else {
        const double d = phi(x, n);
        if (d >= margin) return false;
        for (int a = 0; a < 3; ++a) target[a] = x[a] + (margin - d) * n[a];
    }
    // Velocity relative to the surface: reflect the approaching normal part, damp the
    // tangential part by friction proportional to the normal change (Coulomb-like).
    const vec3 vc = velocity_at(target);
    vec3 rel{v[0] - vc[0], v[1] - vc[1], v[2] - vc[2]};
    const double vn = dot(rel, n);
    if (vn < 0) {
        vec3 vt{rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]};
        const double vt_len = std::sqrt(dot(vt, vt));
        const double dvn = (1 + c_->restitution) * -vn;
        const double keep = vt_len > 0 ? std::max(0.0, 1 - c_->friction * dvn / vt_len) : 0;
        for (int a = 0; a < 3; ++a) v[a] = vc[a] + vt[a] * keep - c_->restitution * vn * n[a];
    }
    x = target;
    return true;
}

std::vector<posed_collider> collider_set::at(double t) const {
    std::vector<posed_collider> out;
    out.reserve(list_.size());
    for (const auto& c : list_) out.emplace_back(c, t);
    return out;
}

void flatten_to_2d(collider& c) {
    c.center[2] = 0;
    // Dropping z shortens the normal: back to unit length then, and only then, so that a
    // flat scene written and read again keeps its normal bit for bit.
    if (c.normal[2] != 0) {
        c.normal[2] = 0;
        c.normal = normalized(c.normal);
    }
    c.path.velocity[2] = 0;
    c.path.amplitude[2] = 0;
    // In the plane, the only rotation keeping z = 0 is about z.
    const vec3 k = normalized(c.axis);
    const double sign = k[2] < 0 ? -1 : 1;
    c.axis = {0, 0, 1};
    c.angle *= sign;
    c.path.angular_velocity *= sign;
    c.half[2] = 1e30;
}

}  // namespace frnn::sim
