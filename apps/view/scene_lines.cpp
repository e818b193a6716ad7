#include "scene_lines.hpp"

#include <cmath>

namespace frnn::view {
namespace {

using sim::vec3;
constexpr std::array<float, 3> domain_color{0.55f, 0.55f, 0.6f}, collider_color{0.9f, 0.6f, 0.3f};

struct line_list {
    std::vector<line_vertex>& out;
    std::array<float, 3> color;
    void add(const vec3& a, const vec3& b) {
        out.push_back({float(a[0]), float(a[1]), float(a[2]), color[0], color[1], color[2]});
        out.push_back({float(b[0]), float(b[1]), float(b[2]), color[0], color[1], color[2]});
    }
};

/// The 12 edges of a box given by a map from its local corner signs (-1 or 1) to the world.
template <class Corner>
void box_edges(line_list& lines, bool flat, Corner corner) {
    if (flat) {  // a 2D box: its rectangle in the xy plane
        const vec3 c[4] = {corner(-1, -1, 0), corner(1, -1, 0), corner(1, 1, 0), corner(-1, 1, 0)};
        for (int k = 0; k < 4; ++k) lines.add(c[k], c[(k + 1) % 4]);
        return;
    }
    for (int a = 0; a < 3; ++a)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2) {
                int lo[3], hi[3];
                const int b = (a + 1) % 3, c = (a + 2) % 3;
                lo[a] = -1, hi[a] = 1, lo[b] = hi[b] = s1, lo[c] = hi[c] = s2;
                lines.add(corner(lo[0], lo[1], lo[2]), corner(hi[0], hi[1], hi[2]));
            }
}

void circle(line_list& lines, const sim::posed_collider& p, int axis_u, int axis_v, double radius) {
    const int segments = 48;
    vec3 prev{};
    for (int k = 0; k <= segments; ++k) {
        const double angle = 2 * 3.14159265358979 * k / segments;
        vec3 local{0, 0, 0};
        local[axis_u] = radius * std::cos(angle);
        local[axis_v] = radius * std::sin(angle);
        const vec3 w = p.to_world(local);
        if (k > 0) lines.add(prev, w);
        prev = w;
    }
}

}  // namespace

double scene_size(const sim::scene& s) {
    vec3 extent{};
    for (int a = 0; a < 3; ++a) extent[a] = s.domain_max[a] - s.domain_min[a];
    return std::sqrt(extent[0] * extent[0] + extent[1] * extent[1] + (s.dim == 2 ? 0 : extent[2] * extent[2]));
}

void collider_lines(std::vector<line_vertex>& out, const sim::posed_collider& p, bool flat, double size,
                    const std::array<float, 3>& color) {
    line_list colliders{out, color};
    const sim::collider& c = p.desc();
    if (c.kind == sim::shape::box) {
        box_edges(colliders, flat, [&](int i, int j, int k) {
            return p.to_world({i * c.half[0], j * c.half[1], flat ? 0.0 : k * c.half[2]});
        });
    } else if (c.kind == sim::shape::sphere) {
        circle(colliders, p, 0, 1, c.radius);
        if (!flat) circle(colliders, p, 1, 2, c.radius), circle(colliders, p, 0, 2, c.radius);
    } else {
        // A square of the domain's size in the plane, centered on the plane's point.
        const vec3 o = p.to_world({0, 0, 0});
        vec3 n{};
        p.phi(o, n);
        vec3 u = std::abs(n[2]) < 0.9 ? vec3{-n[1], n[0], 0} : vec3{1, 0, 0};  // in the plane
        const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (double& x : u) x /= ul;
        const vec3 v{n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
        const double h = 0.5 * size;
        auto at = [&](double a, double b) { return vec3{o[0] + a * u[0] + b * v[0], o[1] + a * u[1] + b * v[1], o[2] + a * u[2] + b * v[2]}; };
        if (flat) {
            colliders.add(at(-h, 0), at(h, 0));
        } else {
            const vec3 q[4] = {at(-h, -h), at(h, -h), at(h, h), at(-h, h)};
            for (int k = 0; k < 4; ++k) colliders.add(q[k], q[(k + 1) % 4]);
            colliders.add(q[0], q[2]);
            colliders.add(q[1], q[3]);
        }
    }
}

std::vector<line_vertex> scene_lines(const sim::scene& s, double t) {
    std::vector<line_vertex> out;
    const bool flat = s.dim == 2;
    line_list domain{out, domain_color};
    box_edges(domain, flat, [&](int i, int j, int k) {
        const int sign[3] = {i, j, k};
        vec3 p{};
        for (int a = 0; a < 3; ++a) p[a] = sign[a] < 0 ? s.domain_min[a] : s.domain_max[a];
        if (flat) p[2] = 0;
        return p;
    });
    const sim::collider_set set(s.colliders);
    const double size = scene_size(s);
    for (const auto& p : set.at(t)) collider_lines(out, p, flat, size, collider_color);
    return out;
}

}  // namespace frnn::view
