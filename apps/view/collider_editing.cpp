#include "collider_editing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace frnn::view {
namespace {

vec3f to_f(const sim::vec3& a) { return {float(a[0]), float(a[1]), float(a[2])}; }
constexpr float none = std::numeric_limits<float>::infinity();

/// Distance along the ray to where it enters the solid of an obstacle sphere or box.
float solid_entry(const sim::posed_collider& p, const pointer_ray& ray) {
    const sim::collider& c = p.desc();
    if (c.inside || c.kind == sim::shape::plane) return none;
    const vec3f center = to_f(p.to_world({0, 0, 0}));
    if (c.kind == sim::shape::sphere) {
        const vec3f oc = center - ray.origin;
        const float along = dot(oc, ray.dir), d2 = dot(oc, oc) - along * along, r2 = float(c.radius * c.radius);
        if (d2 > r2) return none;
        const float entry = along - std::sqrt(r2 - d2);
        return entry > 0 ? entry : none;
    }
    // A box: the slabs of its three local axes (columns of its rotation).
    float enter = -none, leave = none;
    for (int a = 0; a < 3; ++a) {
        sim::vec3 unit{0, 0, 0};
        unit[a] = 1;
        const vec3f axis = to_f(p.to_world(unit)) - center;
        const float o = dot(ray.origin - center, axis), d = dot(ray.dir, axis), h = float(c.half[a]);
        if (std::abs(d) < 1e-12f) {
            if (std::abs(o) > h) return none;
            continue;
        }
        float t0 = (-h - o) / d, t1 = (h - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0), leave = std::min(leave, t1);
    }
    // From inside (a 2D box is unbounded in z, so the plane view's rays start in it): at once.
    return enter <= leave && leave > 0 ? std::max(enter, 0.f) : none;
}

/// Distance along the ray to the point nearest a segment of the outline within the pick
/// tolerance there.
float outline_hit(const std::vector<line_vertex>& lines, const pointer_ray& ray) {
    float best = none;
    for (std::size_t k = 0; k + 1 < lines.size(); k += 2) {
        const vec3f a{lines[k].x, lines[k].y, lines[k].z}, b{lines[k + 1].x, lines[k + 1].y, lines[k + 1].z};
        // The segment's point nearest the ray's line, then the ray's point nearest that.
        const vec3f d = b - a, r = a - ray.origin;
        const float dd = dot(d, d), dr = dot(d, ray.dir);
        const float denom = dd - dr * dr;
        float u = denom > 1e-12f * dd ? (dr * dot(r, ray.dir) - dot(r, d)) / denom : 0;
        u = std::clamp(u, 0.f, 1.f);
        const vec3f q = a + u * d;
        const float along = dot(q - ray.origin, ray.dir);
        if (along <= 0) continue;
        const vec3f off = q - ray.at(along);
        if (std::sqrt(dot(off, off)) <= outline_pick_pixels * ray.pixel_at(along)) best = std::min(best, along);
    }
    return best;
}

}  // namespace

std::optional<std::size_t> pick_collider(const sim::scene& s, double t, const pointer_ray& ray) {
    const sim::collider_set set(s.colliders);
    const double size = scene_size(s);
    float best = none;
    std::optional<std::size_t> hit;
    std::vector<line_vertex> lines;
    const auto posed = set.at(t);
    for (std::size_t k = 0; k < posed.size(); ++k) {
        lines.clear();
        collider_lines(lines, posed[k], s.dim == 2, size, {0, 0, 0});
        const float d = std::min(solid_entry(posed[k], ray), outline_hit(lines, ray));
        if (d < best) best = d, hit = k;
    }
    return hit;
}

std::vector<line_vertex> selection_outline(const sim::scene& s, double t, std::optional<std::size_t> selected) {
    std::vector<line_vertex> out;
    if (!selected || *selected >= s.colliders.size()) return out;
    const sim::posed_collider p(s.colliders[*selected], t);
    collider_lines(out, p, s.dim == 2, scene_size(s), {1.0f, 0.95f, 0.3f});
    return out;
}

std::optional<sim::vec3> on_plane(const pointer_ray& ray, const sim::vec3& point, const vec3f& normal) {
    const float facing = dot(ray.dir, normal);
    if (std::abs(facing) < 1e-6f) return std::nullopt;
    const float along = dot(to_f(point) - ray.origin, normal) / facing;
    const vec3f p = ray.at(along);
    return sim::vec3{p[0], p[1], p[2]};
}

sim::collider turned(sim::collider c, const sim::vec3& axis, double radians) {
    // Quaternions compose the turn with the collider's (axis, angle) and give one back.
    using quat = std::array<double, 4>;  // w, x, y, z
    const auto from = [](const sim::vec3& k, double angle) {
        const double l = std::sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]), s = std::sin(angle / 2) / (l > 0 ? l : 1);
        return quat{std::cos(angle / 2), k[0] * s, k[1] * s, k[2] * s};
    };
    const quat a = from(axis, radians), b = from(c.axis, c.angle);
    const quat q{a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                 a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
    const double v = std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (v < 1e-12) {  // back to no rotation: keep the axis, the one a scripted spin turns about
        c.angle = 0;
        return c;
    }
    c.axis = {q[1] / v, q[2] / v, q[3] / v};
    c.angle = 2 * std::atan2(v, q[0]);
    return c;
}

sim::vec3 free_spot(const sim::scene& s, const std::vector<float>& x, const sim::vec3& at, double reach, double clearance) {
    // Particles binned by cubes of side `clearance` (counting sort), so a candidate looks at the
    // particles of its cube and the 26 around it only; candidates every quarter of a cube.
    const int dims = s.dim;
    std::array<int, 3> n{1, 1, 1};
    for (int a = 0; a < dims; ++a) n[a] = std::max(1, int(std::ceil((s.domain_max[a] - s.domain_min[a]) / clearance)));
    const auto cell_of = [&](int a, double v) {
        return a < dims ? std::clamp(int(std::floor((v - s.domain_min[a]) / clearance)), 0, n[a] - 1) : 0;
    };
    const auto index = [&](int i, int j, int k) { return (std::size_t(k) * std::size_t(n[1]) + std::size_t(j)) * std::size_t(n[0]) + std::size_t(i); };
    const std::size_t cells = std::size_t(n[0]) * std::size_t(n[1]) * std::size_t(n[2]), count = x.size() / 3;
    std::vector<std::size_t> start(cells + 1, 0), order(count);
    const auto cell_of_particle = [&](std::size_t p) { return index(cell_of(0, x[p * 3]), cell_of(1, x[p * 3 + 1]), cell_of(2, x[p * 3 + 2])); };
    for (std::size_t p = 0; p < count; ++p) ++start[cell_of_particle(p) + 1];
    for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < count; ++p) order[fill[cell_of_particle(p)]++] = p;

    const auto free_at = [&](const sim::vec3& c) {
        const int ci = cell_of(0, c[0]), cj = cell_of(1, c[1]), ck = cell_of(2, c[2]);
        for (int k = std::max(ck - 1, 0); k <= std::min(ck + 1, n[2] - 1); ++k)
            for (int j = std::max(cj - 1, 0); j <= std::min(cj + 1, n[1] - 1); ++j)
                for (int i = std::max(ci - 1, 0); i <= std::min(ci + 1, n[0] - 1); ++i)
                    for (std::size_t q = start[index(i, j, k)]; q < start[index(i, j, k) + 1]; ++q) {
                        const std::size_t p = order[q];
                        double d2 = 0;
                        for (int a = 0; a < 3; ++a) d2 += (x[p * 3 + std::size_t(a)] - c[a]) * (x[p * 3 + std::size_t(a)] - c[a]);
                        if (d2 < clearance * clearance) return false;
                    }
        return true;
    };
    std::array<int, 3> steps{1, 1, 1};
    for (int a = 0; a < dims; ++a) steps[a] = int(std::floor((s.domain_max[a] - s.domain_min[a] - 2 * reach) / (0.25 * clearance))) + 1;
    sim::vec3 best = at;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < steps[2]; ++k)
        for (int j = 0; j < steps[1]; ++j)
            for (int i = 0; i < steps[0]; ++i) {
                const int c[3] = {i, j, k};
                sim::vec3 center{0, 0, 0};
                for (int a = 0; a < dims; ++a) center[a] = s.domain_min[a] + reach + c[a] * 0.25 * clearance;
                double d2 = 0;
                for (int a = 0; a < 3; ++a) d2 += (center[a] - at[a]) * (center[a] - at[a]);
                if (d2 < best_d2 && free_at(center)) best_d2 = d2, best = center;
            }
    return best;
}

sim::collider new_collider(sim::shape kind, const sim::scene& s, const sim::vec3& at, const std::vector<float>& particles,
                           double spacing) {
    sim::collider c;
    c.kind = kind;
    double side = std::numeric_limits<double>::infinity();
    for (int a = 0; a < s.dim; ++a) side = std::min(side, s.domain_max[a] - s.domain_min[a]);
    c.radius = 0.1 * side;
    c.half = {c.radius, c.radius, c.radius};
    // A box's corners reach sqrt(dim) half sides from its center.
    const double reach = kind == sim::shape::box ? c.radius * std::sqrt(double(s.dim)) : c.radius;
    c.center = free_spot(s, particles, at, reach, reach + spacing);
    const std::string base = kind == sim::shape::sphere ? "sphere " : "box ";
    for (int n = 1;; ++n) {
        c.name = base + std::to_string(n);
        if (std::none_of(s.colliders.begin(), s.colliders.end(), [&](const sim::collider& o) { return o.name == c.name; })) break;
    }
    if (s.dim == 2) sim::flatten_to_2d(c);
    return c;
}

}  // namespace frnn::view
