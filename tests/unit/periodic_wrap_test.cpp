// frnn::wrap_into_box against a reference written from its definition with std::fmod alone:
// the CPU grid and the oracle share the function, so only this test (and the Vulkan grid's
// own GLSL version) can catch it wrapping wrongly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "frnn/periodic_wrap.hpp"

namespace {

template <class T>
T reference(T x, T length) {
    T w = std::fmod(x, length);  // exact: x - k L for the integer k = trunc(x / L)
    if (w < 0) w += length;
    if (w >= length) w = 0;
    return w == 0 ? T(0) : w;
}

template <class T>
void check(T x, T length) {
    const T w = frnn::wrap_into_box(x, length);
    EXPECT_GE(w, T(0)) << x << " in a box of " << length;
    EXPECT_LT(w, length) << x << " in a box of " << length;
    EXPECT_EQ(w, reference(x, length)) << x << " in a box of " << length;
    if (x >= 0 && x < length) EXPECT_EQ(std::signbit(w), std::signbit(x)) << "a point in the box stays as it is (-0 too)";
    else EXPECT_FALSE(std::signbit(w)) << x << " in a box of " << length << ": -0 is given as 0";
}

template <class T>
void sweep(std::uint64_t seed) {
    using lim = std::numeric_limits<T>;
    std::mt19937_64 rng(seed);
    const std::vector<T> lengths = {T(1), T(7.5), T(0.1), T(3e-30), lim::denorm_min() * 7, lim::max() / 3, lim::max()};
    for (T length : lengths) {
        std::vector<T> xs = {T(0), -T(0), length, -length, std::nextafter(length, T(0)),
                             std::nextafter(-length, T(0)), lim::denorm_min(),
                             -lim::denorm_min(), lim::max(), -lim::max(), lim::min(), -lim::min()};
        std::uniform_real_distribution<double> boxes(-4, 4), fraction(0, 1);
        auto add = [&](double v) {  // in T's range only: converting beyond it is undefined
            if (std::abs(v) <= double(lim::max())) xs.push_back(T(v));
        };
        add(2 * double(length)), add(-2 * double(length)), add(3 * double(length)), add(-3 * double(length));
        for (int k = 0; k < 200; ++k) {
            const double scale = std::pow(10.0, boxes(rng) * 3);  // up to 10^12 boxes out
            add(double(length) * boxes(rng) * scale);
            add(double(length) * (std::floor(boxes(rng)) + fraction(rng)));
        }
        for (T x : xs) check(x, length);
    }
}

TEST(periodic_wrap, equals_the_fmod_definition_in_float_and_double) {
    sweep<float>(1);
    sweep<double>(2);
}

}  // namespace
