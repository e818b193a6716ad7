// The build's vector code for the slots of a uniform grid gives, for every point, the slot
// that grid_geometry gives: per axis trunc(clamp((double(x) - lo) * inv, 0, top)), combined as
// x + stride1 * y + stride2 * z. Checked on cell borders, points outside the frame, and every
// batch length around the vector width.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/sweep.hpp"
#include "frnn/grid_geometry.hpp"

namespace {

// The slot that grid_geometry, the definition every other part of the grid uses, gives x.
template <class T, int D>
std::uint32_t reference_slot(const T* x, const frnn::detail::uniform_frame& f, const std::int64_t* dims) {
    frnn::grid_geometry<T> g;
    g.kind = frnn::grid_kind::uniform;
    for (int a = 0; a < 3; ++a) g.origin[a] = f.lo[a], g.inv_cell[a] = f.inv[a], g.dims[a] = a < D ? dims[a] : 1;
    std::array<T, D> p;
    for (int a = 0; a < D; ++a) p[a] = x[a];
    return std::uint32_t(g.slot_of_cell(g.cell_of(p)));
}

template <class T, int D>
void check_slots() {
    frnn::detail::uniform_frame f{};
    const double cell = 0.7;
    const std::int64_t dims[3] = {37, 23, 11};
    for (int a = 0; a < 3; ++a) f.lo[a] = -3.1 + a, f.inv[a] = 1.0 / cell, f.top[a] = double(dims[a] - 1);
    f.stride1 = std::uint32_t(dims[0]);
    f.stride2 = std::uint32_t(dims[0] * dims[1]);

    // Values on and next to cell borders, outside the frame on both sides, and random ones.
    std::mt19937_64 rng(11);
    std::vector<T> coords;
    for (int k = 0; k < 600; ++k) {
        for (int a = 0; a < D; ++a) {
            const double border = f.lo[a] + cell * double(std::int64_t(rng() % 45) - 3);
            T v = T(border);
            switch (k % 6) {
                case 1: v = std::nextafter(v, T(-1e30)); break;
                case 2: v = std::nextafter(v, T(1e30)); break;
                case 3: v = T(std::uniform_real_distribution<double>(-40, 60)(rng)); break;
                case 4: v = T(k % 12 == 4 ? -1e30 : 1e30); break;
                case 5: v = T(f.lo[a]); break;
                default: break;
            }
            coords.push_back(v);
        }
    }
    const std::size_t n = coords.size() / D;
    const auto& kernels = frnn::detail::sweep_for_cpu<T, D>();
    std::vector<std::uint32_t> out(n + 1);
    // Every batch [b, e) with b and e around multiples of the vector width.
    for (std::size_t b : {std::size_t(0), std::size_t(1), std::size_t(15), std::size_t(16), std::size_t(17)}) {
        for (std::size_t len = 0; len <= 70; ++len) {
            const std::size_t e = b + len;
            if (e > n) break;
            out.assign(n + 1, 0xDEADBEEFu);
            kernels.uniform_slots(coords.data(), b, e, f, out.data());
            for (std::size_t i = b; i < e; ++i)
                ASSERT_EQ(out[i - b], (reference_slot<T, D>(&coords[i * D], f, dims))) << "point " << i << " of [" << b << ", " << e << ")";
            ASSERT_EQ(out[len], 0xDEADBEEFu) << "wrote past the batch [" << b << ", " << e << ")";
        }
    }
    kernels.uniform_slots(coords.data(), 0, n, f, out.data());
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(out[i], (reference_slot<T, D>(&coords[i * D], f, dims))) << "point " << i;
}

}  // namespace

TEST(uniform_slots, float_3d_match_the_formula) { check_slots<float, 3>(); }
TEST(uniform_slots, float_2d_match_the_formula) { check_slots<float, 2>(); }
TEST(uniform_slots, double_3d_match_the_formula) { check_slots<double, 3>(); }
TEST(uniform_slots, double_2d_match_the_formula) { check_slots<double, 2>(); }
