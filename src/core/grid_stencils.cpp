// The runs of sorted points around a cell: its whole stencil or the forward half of it, on the
// uniform grid (rows of cells are runs of points), the periodic box (wrapped, with each run's
// image) and the hashed grid (rows of cells through the table).
#include <algorithm>
#include <array>
#include <cstdint>

#include "frnn/grid.hpp"

namespace frnn {

namespace {

// append_run for runs with images: touching runs merge only when their images agree.
void append_imaged_run(detail::candidate_run* out, detail::run_image* images, std::size_t& n, std::uint32_t b,
                       std::uint32_t e, const detail::run_image& image) {
    if (b == e) return;
    // Element by element: std::array's == calls memcmp (a quarter of W8's time with cells of r/2).
    const detail::run_image& last = images[n > 0 ? n - 1 : 0];
    if (n > 0 && out[n - 1].end == b && last[0] == image[0] && last[1] == image[1] && last[2] == image[2]) {
        out[n - 1].end = e;
        return;
    }
    images[n] = image;
    out[n++] = {b, e};
}

}  // namespace

template <class T, int D>
bool grid<T, D>::images_exact() const {
    if (!geometry_.periodic) return false;
    for (int a = 0; a < D; ++a)
        if (geometry_.wraps[a] && geometry_.dims[a] < 2 * geometry_.reach + 3) return false;
    return true;
}

template <class T, int D>
std::size_t grid<T, D>::stencil_runs(const std::array<std::int64_t, 3>& c, detail::candidate_run* out,
                                     std::int64_t width, detail::run_image* images) const {
    std::size_t n = 0;
    const int k = geometry_.reach;
    auto add = [&](std::uint32_t b, std::uint32_t e) { detail::append_run(out, n, b, e); };
    const int zr = D == 3 ? k : 0;
    if (geometry_.kind == grid_kind::uniform && !geometry_.periodic) {
        const std::int64_t x0 = std::max<std::int64_t>(0, c[0] - k);
        const std::int64_t x1 = std::min<std::int64_t>(geometry_.dims[0] - 1, c[0] + width - 1 + k);
        for (int dz = -zr; dz <= zr; ++dz) {
            const std::int64_t z = c[2] + dz;
            if (z < 0 || z >= geometry_.dims[2]) continue;
            for (int dy = -k; dy <= k; ++dy) {
                const std::int64_t y = c[1] + dy;
                if (y < 0 || y >= geometry_.dims[1]) continue;
                const auto row = std::int64_t(geometry_.slot_of_cell({0, y, z}));
                add(offsets_[row + x0], offsets_[row + x1 + 1]);
            }
        }
        return n;
    }
    if (geometry_.periodic) {
        // Along y and z, the stencil's distinct wrapped cells in increasing order (so the runs
        // come in order of sorted index), each with its image: every cell, image 0, when the
        // axis has no more than 2k + 1 of them; those within the grid on an open axis.
        std::array<std::array<std::int64_t, 9>, 3> idx{};
        std::array<std::array<std::int8_t, 9>, 3> img{};
        std::array<int, 3> count{1, 1, 1};
        for (int a = 1; a < D; ++a) {
            const std::int64_t cells = geometry_.dims[a];
            if (!geometry_.wraps[a]) {
                count[a] = 0;
                for (std::int64_t u = std::max<std::int64_t>(0, c[a] - k); u <= std::min(cells - 1, c[a] + k); ++u)
                    idx[a][count[a]++] = u;
                continue;
            }
            if (cells <= 2 * k + 1) {
                count[a] = int(cells);
                for (int i = 0; i < count[a]; ++i) idx[a][i] = i;
                continue;
            }
            count[a] = 2 * k + 1;
            for (int d = -k; d <= k; ++d) {
                const std::int64_t u = c[a] + d;
                const std::int64_t wrapped = (u % cells + cells) % cells;
                // Insertion by cell index: a candidate wrapped from above sits at d - L.
                int i = d + k;
                for (; i > 0 && idx[a][i - 1] > wrapped; --i) idx[a][i] = idx[a][i - 1], img[a][i] = img[a][i - 1];
                idx[a][i] = wrapped;
                img[a][i] = std::int8_t(u < 0 ? 1 : u >= cells ? -1 : 0);
            }
        }
        // Along x, the stencil's cells of a row are one or two segments of consecutive cells,
        // in increasing order, each one run.
        struct segment {
            std::int64_t from, to;
            std::int8_t image;
        };
        std::array<segment, 2> xs{};
        int nx = 0;
        {
            const std::int64_t cells = geometry_.dims[0], lo = c[0] - k, hi = c[0] + k;
            if (!geometry_.wraps[0]) xs[nx++] = {std::max<std::int64_t>(0, lo), std::min(cells - 1, hi), 0};
            else if (cells <= 2 * k + 1) xs[nx++] = {0, cells - 1, 0};
            else if (lo < 0) xs[nx++] = {0, hi, 0}, xs[nx++] = {lo + cells, cells - 1, 1};
            else if (hi >= cells) xs[nx++] = {0, hi - cells, -1}, xs[nx++] = {lo, cells - 1, 0};
            else xs[nx++] = {lo, hi, 0};
        }
        for (int iz = 0; iz < count[2]; ++iz)
            for (int iy = 0; iy < count[1]; ++iy) {
                const auto row = std::int64_t(geometry_.slot_of_cell({0, idx[1][iy], idx[2][iz]}));
                for (int ix = 0; ix < nx; ++ix) {
                    const std::uint32_t b = offsets_[row + xs[ix].from], e = offsets_[row + xs[ix].to + 1];
                    if (!images) {
                        add(b, e);
                        continue;
                    }
                    append_imaged_run(out, images, n, b, e, {xs[ix].image, img[1][iy], img[2][iz]});
                }
            }
        return n;
    }
    return hashed_runs(c, false, out);
}

// The rows of cells of the stencil (or its forward half: the row of `c` from `c` on first)
// through the table: consecutive x cells are consecutive slots.
template <class T, int D>
std::size_t grid<T, D>::hashed_runs(const std::array<std::int64_t, 3>& c, bool forward,
                                    detail::candidate_run* out) const {
    std::size_t n = 0;
    auto row = [&](std::int64_t y, std::int64_t z, std::int64_t x0, std::int64_t x1) {
        for (std::int64_t x = x0; x <= x1; ++x) {
            const auto [b, e] = hashed_cell_points({x, y, z});
            detail::append_run(out, n, b, e);
        }
    };
    const int k = geometry_.reach;
    const int zr = D == 3 ? k : 0;
    if (!forward) {
        for (int dz = -zr; dz <= zr; ++dz)
            for (int dy = -k; dy <= k; ++dy) row(c[1] + dy, c[2] + dz, c[0] - k, c[0] + k);
        return n;
    }
    row(c[1], c[2], c[0], c[0] + k);
    for (int dy = 1; dy <= k; ++dy) row(c[1] + dy, c[2], c[0] - k, c[0] + k);
    for (int dz = 1; dz <= zr; ++dz)
        for (int dy = -k; dy <= k; ++dy) row(c[1] + dy, c[2] + dz, c[0] - k, c[0] + k);
    return n;
}

template <class T, int D>
std::pair<std::uint32_t, std::uint32_t> grid<T, D>::hashed_cell_points(const std::array<std::int64_t, 3>& cell) const {
    const std::size_t s = geometry_.slot_of_cell(cell);
    const std::uint32_t k = occupied_index(s);
    if (k == empty_slot) return {0, 0};
    std::uint32_t b = offsets_[k], e = offsets_[k + 1];
    if (shared_slots_[k / 64] >> (k % 64) & 1) {
        // A shared slot holds its cells one after the other, ordered by cell coordinates
        // (mark_shared_slots): two binary searches find the cell's points.
        auto first_failing = [](std::uint32_t lo, std::uint32_t hi, auto&& pred) {
            while (lo < hi) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                if (pred(mid)) lo = mid + 1;
                else hi = mid;
            }
            return lo;
        };
        b = first_failing(b, e, [&](std::uint32_t j) { return cell_of(sorted_point(j)) < cell; });
        if (b == e || !hashed_point_in_cell(b, cell)) return {b, b};
        return {b, first_failing(b + 1, e, [&](std::uint32_t j) { return hashed_point_in_cell(j, cell); })};
    }
    if (!hashed_point_in_cell(b, cell)) return {b, b};
    return {b, e};
}

template <class T, int D>
std::size_t grid<T, D>::forward_runs(const std::array<std::int64_t, 3>& c, detail::candidate_run* out,
                                     std::int64_t width, detail::run_image* images) const {
    const int k = geometry_.reach;
    std::size_t n = 0;
    if (geometry_.kind == grid_kind::hashed)  // the same cells, found through the table
        return hashed_runs(c, true, out);
    if (geometry_.periodic) {
        // Wrapped on the periodic axes, cut at the grid's ends on open ones. With 2k + 1 cells
        // or more on every periodic axis (the caller's condition) the cells c + d are
        // distinct, and of d and -d exactly one lies in the half.
        auto wrapped = [&](int a, std::int64_t v) { return (v % geometry_.dims[a] + geometry_.dims[a]) % geometry_.dims[a]; };
        // A candidate wrapped from above sits at d - L: image -1; from below, +1.
        auto image_of = [&](int a, std::int64_t v) { return std::int8_t(v < 0 ? 1 : v >= geometry_.dims[a] ? -1 : 0); };
        // Runs merge only within a layer of cells (z in 3D, y in 2D): a sweep of a slab of
        // layers sends each run's partner counts to one place, its own points or the next
        // slab's, by where the run starts (partner_sink). With 2 reach + 1 cells on an axis the
        // last row of one layer and the first of the next can both be in the half-stencil.
        std::int64_t last_layer = -1;
        auto add = [&](std::uint32_t b, std::uint32_t e, const detail::run_image& image, std::int64_t layer) {
            if (b == e) return;
            if (layer != last_layer) {
                last_layer = layer;
                if (images) images[n] = image;
                out[n++] = {b, e};
                return;
            }
            if (images) append_imaged_run(out, images, n, b, e, image);
            else detail::append_run(out, n, b, e);
        };
        auto outside = [&](int a, std::int64_t v) { return !geometry_.wraps[a] && (v < 0 || v >= geometry_.dims[a]); };
        auto add_cells = [&](std::int64_t y, std::int64_t z, std::int64_t from, std::int64_t to) {
            if (outside(1, y) || (D == 3 && outside(2, z))) return;
            if (!geometry_.wraps[0]) from = std::max<std::int64_t>(from, 0), to = std::min(to, geometry_.dims[0] - 1);
            const std::int64_t layer = D == 3 ? wrapped(2, z) : wrapped(1, y);
            const auto row = std::int64_t(geometry_.slot_of_cell({0, wrapped(1, y), wrapped(2, z)}));
            const std::int64_t a = wrapped(0, from), b = wrapped(0, to);
            const std::int8_t iy = image_of(1, y), iz = D == 3 ? image_of(2, z) : std::int8_t(0);
            if (a <= b) {
                add(offsets_[row + a], offsets_[row + b + 1], {image_of(0, from), iy, iz}, layer);
            } else {
                add(offsets_[row + a], offsets_[row + geometry_.dims[0]], {image_of(0, from), iy, iz}, layer);
                add(offsets_[row], offsets_[row + b + 1], {image_of(0, to), iy, iz}, layer);
            }
        };
        add_cells(c[1], c[2], c[0], c[0] + k);  // own cell onwards
        for (int dy = 1; dy <= k; ++dy) add_cells(c[1] + dy, c[2], c[0] - k, c[0] + k);
        if constexpr (D == 3) {
            for (int dz = 1; dz <= k; ++dz)
                for (int dy = -k; dy <= k; ++dy) add_cells(c[1] + dy, c[2] + dz, c[0] - k, c[0] + k);
        }
        return n;
    }
    const std::int64_t x0 = std::max<std::int64_t>(0, c[0] - k);
    const std::int64_t x1 = std::min<std::int64_t>(geometry_.dims[0] - 1, c[0] + width - 1 + k);
    auto add_row = [&](std::int64_t y, std::int64_t z, std::int64_t from) {
        const auto row = std::int64_t(geometry_.slot_of_cell({0, y, z}));
        const std::uint32_t b = offsets_[row + from], e = offsets_[row + x1 + 1];
        if (b < e) out[n++] = {b, e};
    };
    add_row(c[1], c[2], c[0]);  // own cell onwards
    for (int dy = 1; dy <= k && c[1] + dy < geometry_.dims[1]; ++dy) add_row(c[1] + dy, c[2], x0);
    if constexpr (D == 3) {
        for (int dz = 1; dz <= k && c[2] + dz < geometry_.dims[2]; ++dz)
            for (int dy = -k; dy <= k; ++dy) {
                const std::int64_t y = c[1] + dy;
                if (y >= 0 && y < geometry_.dims[1]) add_row(y, c[2] + dz, x0);
            }
    }
    return n;
}

// The class itself is instantiated in grid_build.cpp (grid.hpp declares it extern, so nothing
// here is instantiated implicitly); these are the members defined here.
#define FRNN_INSTANTIATE_STENCILS(T, D)                                                                      \
    template bool grid<T, D>::images_exact() const;                                                         \
    template std::size_t grid<T, D>::stencil_runs(const std::array<std::int64_t, 3>&, detail::candidate_run*, \
                                                  std::int64_t, detail::run_image*) const;                  \
    template std::size_t grid<T, D>::forward_runs(const std::array<std::int64_t, 3>&, detail::candidate_run*, \
                                                  std::int64_t, detail::run_image*) const;                  \
    template std::size_t grid<T, D>::hashed_runs(const std::array<std::int64_t, 3>&, bool,                  \
                                                 detail::candidate_run*) const;                             \
    template std::pair<std::uint32_t, std::uint32_t> grid<T, D>::hashed_cell_points(                        \
        const std::array<std::int64_t, 3>&) const;
FRNN_INSTANTIATE_STENCILS(float, 2)
FRNN_INSTANTIATE_STENCILS(float, 3)
FRNN_INSTANTIATE_STENCILS(double, 2)
FRNN_INSTANTIATE_STENCILS(double, 3)

}  // namespace frnn
