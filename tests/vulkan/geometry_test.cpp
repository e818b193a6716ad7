// vulkan::grid::geometry(): the device grid's cells, laid out by the CPU grid's rules, against
// what the device does: it agrees with kind(), slot_count() and search_scale(); every neighbor
// within r of a point lies in a cell of cells_within(point); and the device's cell order
// follows slot_of_cell(cell_of(x)) on uniform grids (points within 2^-12 of a cell face, where
// float and double may round to different cells, aside). Uniform, hashed and periodic grids,
// 2D and 3D, with far outliers.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "frnn/brute_force.hpp"
#include "oracle/point_sets.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using frnn::test::uniform_points;

class vulkan_geometry : public vulkan_test {};

// Whether cell c lies in range r, periodic axes taken modulo the cells per axis.
bool in_range(const grid_geometry<float>& geo, const cell_index& c, const cell_range& r, int dim) {
    for (int a = 0; a < dim; ++a) {
        if (geo.periodic) {
            const std::int64_t n = geo.dims[a];
            if (r.last[a] - r.first[a] + 1 < n && ((c[a] - r.first[a]) % n + n) % n > r.last[a] - r.first[a])
                return false;
        } else if (c[a] < r.first[a] || c[a] > r.last[a]) {
            return false;
        }
    }
    return true;
}

// How far x (search space) lies from the nearest cell face, in cells.
double face_distance(const grid_geometry<float>& geo, const float* x, int dim) {
    double nearest = 1;
    for (int a = 0; a < dim; ++a) {
        double u = double(x[a]);
        if (geo.periodic) u -= double(geo.box[a]) * std::floor(u / double(geo.box[a]));
        const double f = (u - geo.origin[a]) * geo.inv_cell[a];
        nearest = std::min({nearest, f - std::floor(f), std::ceil(f) - f});
    }
    return nearest;
}

template <int D>
void check(context& ctx, const std::vector<float>& pts, float r, const grid_options& o, const std::string& name) {
    SCOPED_TRACE(name);
    grid<D> g(ctx);
    g.build(pts, r, o);
    const grid_geometry<float>& geo = g.geometry();
    EXPECT_EQ(geo.kind, g.kind());
    EXPECT_EQ(geo.slots, g.slot_count());
    EXPECT_EQ(geo.scale, g.search_scale());
    EXPECT_EQ(geo.periodic, !o.periodic.empty());

    const std::size_t n = pts.size() / D;
    const csr<float> oracle = frnn::brute_force_lists<float, D>(pts, pts, r, true, o.periodic);
    for (std::size_t i = 0; i < n; ++i) {
        std::array<float, D> x;
        for (int a = 0; a < D; ++a) x[a] = pts[i * D + a] * geo.scale;
        const cell_range visited = geo.cells_within(x);
        for (std::size_t k = oracle.offsets[i]; k < oracle.offsets[i + 1]; ++k) {
            const std::uint32_t j = oracle.indices[k];
            std::array<float, D> y;
            for (int a = 0; a < D; ++a) y[a] = pts[j * D + a] * geo.scale;
            ASSERT_TRUE(in_range(geo, geo.cell_of(y), visited, D)) << "neighbor " << j << " of point " << i;
        }
    }

    if (geo.kind != grid_kind::uniform) return;
    const auto order = g.sorted_to_original();
    std::size_t previous = 0;
    for (std::size_t s = 0; s < order.size(); ++s) {
        std::array<float, D> x;
        for (int a = 0; a < D; ++a) x[a] = pts[order[s] * D + a] * geo.scale;
        if (face_distance(geo, x.data(), D) < 0x1p-12) continue;
        const std::size_t slot = geo.slot_of_cell(geo.cell_of(x));
        ASSERT_LT(slot, geo.slots);
        ASSERT_GE(slot, previous) << "sorted point " << s;
        previous = slot;
    }
}

TEST_F(vulkan_geometry, agrees_with_the_device) {
    for (int dim : {2, 3}) {
        const std::size_t n = dim == 2 ? 3000 : 4000;
        std::vector<float> pts = dim == 2 ? uniform_points<float, 2>(n, 0, 20, 7) : uniform_points<float, 3>(n, 0, 12, 7);
        const float r = 1.0f;
        grid_options uniform, hashed, periodic, small_cells;
        uniform.kind = grid_kind::uniform;
        hashed.kind = grid_kind::hashed;
        small_cells.cell_size = 0.5;
        periodic.periodic.assign(dim, dim == 2 ? 20.0 : 12.0);
        std::vector<float> outliers = pts;
        outliers[0] = 3e6f, outliers[dim] = -2e5f;  // far out: the automatic choice hashes
        if (dim == 2) {
            check<2>(ctx(), pts, r, uniform, "2D uniform");
            check<2>(ctx(), pts, r, hashed, "2D hashed");
            check<2>(ctx(), pts, r, small_cells, "2D cells r/2");
            check<2>(ctx(), pts, r, periodic, "2D periodic");
            check<2>(ctx(), outliers, r, {}, "2D outliers");
        } else {
            check<3>(ctx(), pts, r, uniform, "3D uniform");
            check<3>(ctx(), pts, r, hashed, "3D hashed");
            check<3>(ctx(), pts, r, small_cells, "3D cells r/2");
            check<3>(ctx(), pts, r, periodic, "3D periodic");
            check<3>(ctx(), outliers, r, {}, "3D outliers");
        }
    }
}

}  // namespace
}  // namespace frnn::vulkan::test
