// Software renderer: particles as shaded sphere splats with a depth buffer, colored by speed,
// seen by a fixed camera that frames the scene's domain. The domain's edges are drawn as lines.
#include <algorithm>
#include <cmath>
#include <limits>

#include "frnn/sim/output.hpp"

namespace frnn::sim {
namespace {

struct camera {
    vec3 eye, right, up, fwd;
    double focal;  // pixels per unit at depth 1
    double cx, cy;
    bool ortho = false;
    double scale = 1;  // ortho: pixels per unit
    vec3 ortho_min{};
    /// Screen position and depth of a world point; false behind the camera.
    bool project(const vec3& p, double& sx, double& sy, double& depth) const {
        if (ortho) {
            sx = cx + (p[0] - ortho_min[0]) * scale;
            sy = cy - (p[1] - ortho_min[1]) * scale;
            depth = -p[2];
            return true;
        }
        const vec3 d{p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
        depth = d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2];
        if (depth <= 1e-6) return false;
        sx = cx + focal * (d[0] * right[0] + d[1] * right[1] + d[2] * right[2]) / depth;
        sy = cy - focal * (d[0] * up[0] + d[1] * up[1] + d[2] * up[2]) / depth;
        return true;
    }
};

vec3 norm3(vec3 a) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return {a[0] / l, a[1] / l, a[2] / l};
}
vec3 cross3(const vec3& a, const vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

camera make_camera(const scene& s, int w, int h) {
    camera c;
    c.cx = w / 2.0;
    c.cy = h / 2.0;
    const vec3 lo = s.domain_min, hi = s.domain_max;
    if (s.dim == 2) {
        c.ortho = true;
        const double sx = (w * 0.92) / (hi[0] - lo[0]), sy = (h * 0.92) / (hi[1] - lo[1]);
        c.scale = std::min(sx, sy);
        c.cx = (w - c.scale * (hi[0] - lo[0])) / 2;
        c.cy = h - (h - c.scale * (hi[1] - lo[1])) / 2;
        c.ortho_min = lo;
        return c;
    }
    const vec3 center{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    double radius = 0;
    for (int a = 0; a < 3; ++a) radius += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    radius = std::sqrt(radius) / 2;
    const vec3 dir = norm3({0.35, 0.55, 1.0});  // from the front, a little right and above
    const double fov = 40 * 3.14159265358979 / 180, dist = radius / std::sin(fov / 2) * 0.95;
    c.eye = {center[0] + dir[0] * dist, center[1] + dir[1] * dist, center[2] + dir[2] * dist};
    c.fwd = {-dir[0], -dir[1], -dir[2]};
    c.right = norm3(cross3(c.fwd, {0, 1, 0}));
    c.up = cross3(c.right, c.fwd);
    c.focal = (h / 2.0) / std::tan(fov / 2);
    return c;
}

/// Dark blue (still) through azure and cyan to white (fastest).
void speed_color(double t, double rgb[3]) {
    static const double stops[5][3] = {{0.05, 0.15, 0.45}, {0.1, 0.35, 0.8}, {0.2, 0.65, 0.95}, {0.55, 0.9, 1.0}, {1, 1, 1}};
    t = std::clamp(t, 0.0, 1.0) * 4;
    const int k = std::min(3, int(t));
    const double f = t - k;
    for (int c = 0; c < 3; ++c) rgb[c] = stops[k][c] * (1 - f) + stops[k + 1][c] * f;
}

}  // namespace

image render(const particle_view& p, const scene& s, double particle_radius, int w, int h, double max_speed, double t) {
    image img;
    img.width = w;
    img.height = h;
    img.rgb.resize(std::size_t(w) * std::size_t(h) * 3);
    std::vector<float> zbuf(std::size_t(w) * std::size_t(h), std::numeric_limits<float>::infinity());
    for (int y = 0; y < h; ++y) {
        const double fy = double(y) / h;
        for (int x = 0; x < w; ++x) {
            std::uint8_t* px = &img.rgb[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3];
            px[0] = std::uint8_t(235 - 60 * fy);
            px[1] = std::uint8_t(238 - 55 * fy);
            px[2] = std::uint8_t(242 - 40 * fy);
        }
    }
    const camera cam = make_camera(s, w, h);
    const std::size_t D = std::size_t(p.dim);
    std::vector<float> speed(p.n);
    double vmax = max_speed;
    for (std::size_t i = 0; i < p.n; ++i) {
        double s2 = 0;
        for (std::size_t a = 0; a < D; ++a) s2 += double(p.v[i * D + a]) * p.v[i * D + a];
        speed[i] = float(std::sqrt(s2));
        if (max_speed <= 0) vmax = std::max(vmax, double(speed[i]));
    }
    if (vmax <= 0) vmax = 1;
    const vec3 light = norm3({-0.4, 0.8, 0.6});
    // A shaded sphere of world radius `radius` at `pos`, depth-tested.
    auto splat = [&](const vec3& pos, double radius, const double base[3]) {
        double sx, sy, depth;
        if (!cam.project(pos, sx, sy, depth)) return;
        const double rpx = cam.ortho ? radius * cam.scale : radius * cam.focal / depth;
        const double rr = std::max(rpx, 0.7);
        const int x0 = std::max(0, int(std::floor(sx - rr))), x1 = std::min(w - 1, int(std::ceil(sx + rr)));
        const int y0 = std::max(0, int(std::floor(sy - rr))), y1 = std::min(h - 1, int(std::ceil(sy + rr)));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double dx = (x + 0.5 - sx) / rr, dy = (y + 0.5 - sy) / rr, d2 = dx * dx + dy * dy;
                if (d2 > 1) continue;
                const double nz = std::sqrt(1 - d2);
                const float z = float(depth - nz * (cam.ortho ? 0 : radius));
                float& zb = zbuf[std::size_t(y) * std::size_t(w) + std::size_t(x)];
                if (z >= zb) continue;
                zb = z;
                // Normal in camera space (x right, y up, z toward the viewer), light in world.
                vec3 n;
                if (cam.ortho) n = {dx, -dy, nz};
                else
                    for (int a = 0; a < 3; ++a) n[a] = dx * cam.right[a] - dy * cam.up[a] - nz * cam.fwd[a];
                const double lam = std::max(0.0, n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
                const double spec = std::pow(std::max(0.0, nz * 0.6 + lam * 0.4), 24) * 0.35;
                std::uint8_t* px = &img.rgb[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3];
                for (int c = 0; c < 3; ++c)
                    px[c] = std::uint8_t(std::clamp((base[c] * (0.35 + 0.65 * lam) + spec) * 255.0, 0.0, 255.0));
            }
    };
    std::vector<std::pair<vec3, vec3>> edges;
    const double grey[3] = {0.62, 0.6, 0.58};
    const collider_set colliders(s.colliders);  // owns what the posed colliders point to
    for (const auto& c : colliders.at(t)) {
        const collider& d = c.desc();
        if (d.kind == shape::sphere && !d.inside) splat(c.to_world({0, 0, 0}), d.radius, grey);
        if (d.kind == shape::box && !d.inside) {
            for (int a = 0; a < 8; ++a)
                for (int b = a + 1; b < 8; ++b) {
                    const int diff = a ^ b;
                    if (diff != 1 && diff != 2 && diff != 4) continue;
                    auto corner = [&](int k) {
                        vec3 l{k & 1 ? d.half[0] : -d.half[0], k & 2 ? d.half[1] : -d.half[1], k & 4 ? d.half[2] : -d.half[2]};
                        if (s.dim == 2) l[2] = 0;
                        return c.to_world(l);
                    };
                    edges.emplace_back(corner(a), corner(b));
                }
        }
    }
    for (std::size_t i = 0; i < p.n; ++i) {
        vec3 pos{0, 0, 0};
        for (std::size_t a = 0; a < D; ++a) pos[a] = p.x[i * D + a];
        double base[3];
        speed_color(speed[i] / vmax, base);
        splat(pos, particle_radius, base);
    }
    // The domain's edges, depth-tested.
    const vec3 lo = s.domain_min, hi = s.domain_max;
    const int corners = s.dim == 2 ? 4 : 8;
    for (int a = 0; a < corners; ++a)
        for (int b = a + 1; b < corners; ++b) {
            const int diff = a ^ b;
            if (diff != 1 && diff != 2 && diff != 4) continue;
            vec3 pa{a & 1 ? hi[0] : lo[0], a & 2 ? hi[1] : lo[1], s.dim == 2 ? 0 : (a & 4 ? hi[2] : lo[2])};
            vec3 pb{b & 1 ? hi[0] : lo[0], b & 2 ? hi[1] : lo[1], s.dim == 2 ? 0 : (b & 4 ? hi[2] : lo[2])};
            edges.emplace_back(pa, pb);
        }
    for (const auto& [a, b] : edges) {
        const int samples = 2 * (w + h);
        for (int k = 0; k <= samples; ++k) {
            const double u = double(k) / samples;
            const vec3 q{a[0] + (b[0] - a[0]) * u, a[1] + (b[1] - a[1]) * u, a[2] + (b[2] - a[2]) * u};
            double sx, sy, depth;
            if (!cam.project(q, sx, sy, depth)) continue;
            const int x = int(sx), y = int(sy);
            if (x < 0 || y < 0 || x >= w || y >= h) continue;
            if (float(depth) > zbuf[std::size_t(y) * std::size_t(w) + std::size_t(x)]) continue;
            std::uint8_t* px = &img.rgb[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 3];
            px[0] = px[1] = px[2] = 70;
        }
    }
    return img;
}

}  // namespace frnn::sim
