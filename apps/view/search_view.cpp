#include "search_view.hpp"

#include <algorithm>
#include <cmath>

namespace frnn::view {
namespace {

template <std::size_t D>
std::array<float, D> search_space(const sim::particle_snapshot& s, std::size_t k) {
    std::array<float, D> x{};
    for (std::size_t a = 0; a < D; ++a) x[a] = s.x[k * 3 + a] * s.geometry.scale;
    return x;
}

template <std::size_t D>
std::vector<cell_index> block_of(const sim::particle_snapshot& s, const std::array<float, D>& x) {
    const cell_range r = s.geometry.cells_within(x);
    std::vector<cell_index> cells;
    for (auto z = r.first[2]; z <= r.last[2]; ++z)
        for (auto y = r.first[1]; y <= r.last[1]; ++y)
            for (auto c = r.first[0]; c <= r.last[0]; ++c) cells.push_back({c, y, z});
    return cells;
}

std::vector<cell_index> block_around(const sim::particle_snapshot& s, const std::array<float, 3>& p) {
    const float k = s.geometry.scale;
    if (s.dim == 2) return block_of<2>(s, std::array<float, 2>{p[0] * k, p[1] * k});
    return block_of<3>(s, std::array<float, 3>{p[0] * k, p[1] * k, p[2] * k});
}

/// Distance from p to the box of cell c, over the snapshot's axes.
double distance_to_cell(const sim::particle_snapshot& s, const cell_index& c, const std::array<float, 3>& p) {
    const auto box = s.geometry.cell_bounds(c);
    double d2 = 0;
    for (std::size_t a = 0; a < std::size_t(s.dim); ++a) {
        const double outside = std::max({box[0][a] - double(p[a]), 0.0, double(p[a]) - box[1][a]});
        d2 += outside * outside;
    }
    return std::sqrt(d2);
}

}  // namespace

std::vector<cell_index> visited_cells(const sim::particle_snapshot& s, const std::array<float, 3>& p) {
    if (s.geometry.slots == 0) return {};
    return block_around(s, p);
}

particle_search search_of(const sim::particle_snapshot& s, std::size_t id) {
    particle_search out;
    if (s.geometry.slots == 0 || id >= s.n) return out;
    const std::array<float, 3> p{s.x[id * 3], s.x[id * 3 + 1], s.x[id * 3 + 2]};
    for (const cell_index& c : block_around(s, p))
        if (distance_to_cell(s, c, p) <= s.radius) out.cells.push_back(c);
    // Candidates are the particles in those cells, as in the search; a neighbor found anywhere
    // else would mean the cells are wrong, which the viewer tests check by brute force.
    for (std::size_t j = 0; j < s.n; ++j) {
        if (j == id) continue;
        const cell_index c = s.dim == 2 ? s.geometry.cell_of(search_space<2>(s, j)) : s.geometry.cell_of(search_space<3>(s, j));
        if (std::find(out.cells.begin(), out.cells.end(), c) == out.cells.end()) continue;
        double d2 = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            const double d = double(s.x[j * 3 + a]) - double(p[a]);
            d2 += d * d;
        }
        if (std::sqrt(d2) <= s.radius) out.neighbors.push_back(j);
    }
    return out;
}

std::vector<line_vertex> cell_lines(const sim::particle_snapshot& s, const std::vector<cell_index>& cells,
                                    const std::array<float, 3>& color) {
    std::vector<line_vertex> out;
    const auto add = [&](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        out.push_back({float(a[0]), float(a[1]), float(a[2]), color[0], color[1], color[2]});
        out.push_back({float(b[0]), float(b[1]), float(b[2]), color[0], color[1], color[2]});
    };
    for (const cell_index& c : cells) {
        const auto box = s.geometry.cell_bounds(c);
        // Corner k takes axis a's upper bound when bit a of k is set.
        const auto corner = [&](int k) {
            std::array<double, 3> p{};
            for (std::size_t a = 0; a < 3; ++a) p[a] = box[(k >> a) & 1][a];
            if (s.dim == 2) p[2] = 0;
            return p;
        };
        const int corners = s.dim == 2 ? 4 : 8;
        for (int k = 0; k < corners; ++k)
            for (int a = 0; a < s.dim; ++a)
                if (!(k & (1 << a))) add(corner(k), corner(k | (1 << a)));  // each edge once, from its lower end
    }
    return out;
}

}  // namespace frnn::view
