// The cubic spline integrates to one, its derivative matches finite differences, and the
// half-space integral goes from 1/2 at the wall to 0 at the support radius.
#include <gtest/gtest.h>

#include <cmath>

#include "frnn/sim/kernels.hpp"

namespace {
constexpr double pi = 3.14159265358979323846;

template <int D>
double integrate(const frnn::sim::cubic_spline<D>& w) {
    const int n = 4000;
    const double R = w.support(), dr = R / n;
    double s = 0;
    for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * dr;
        s += (D == 3 ? 4 * pi * r * r : 2 * pi * r) * w(r) * dr;
    }
    return s;
}

TEST(SimKernels, CubicSplineIntegratesToOne) {
    for (double R : {0.01, 0.5, 3.0}) {
        EXPECT_NEAR(integrate(frnn::sim::cubic_spline<2>(R)), 1.0, 1e-5) << "2D, R = " << R;
        EXPECT_NEAR(integrate(frnn::sim::cubic_spline<3>(R)), 1.0, 1e-5) << "3D, R = " << R;
    }
}

TEST(SimKernels, CubicSplineDerivativeMatchesFiniteDifference) {
    const frnn::sim::cubic_spline<3> w(0.2);
    for (double r = 0.003; r < 0.2; r += 0.0137) {
        const double e = 1e-6, fd = (w(r + e) - w(r - e)) / (2 * e);
        EXPECT_NEAR(w.derivative(r), fd, 1e-6 * std::abs(w(0)) / 0.2 + 1e-3 * std::abs(fd)) << "r = " << r;
        EXPECT_LE(w.derivative(r), 0);
    }
    EXPECT_EQ(w(0.2), 0);
    EXPECT_EQ(w(0.25), 0);
    EXPECT_GT(w(0.199), 0);
}

TEST(SimKernels, HalfSpaceIntegral) {
    const frnn::sim::cubic_spline<2> w2(1.0);
    const frnn::sim::half_space_integral<2> psi2(w2);
    const frnn::sim::cubic_spline<3> w3(1.0);
    const frnn::sim::half_space_integral<3> psi3(w3);
    EXPECT_NEAR(psi2(0), 0.5, 2e-3);
    EXPECT_NEAR(psi3(0), 0.5, 2e-3);
    EXPECT_EQ(psi3(1.0), 0);
    double last = 1;
    for (double d = 0; d < 1; d += 0.05) {
        EXPECT_LE(psi3(d), last);
        last = psi3(d);
        // The derivative is minus the kernel's integral over the plane at distance d.
        const double e = 1e-3;
        EXPECT_NEAR(psi3.derivative(d + e), (psi3(d + 2 * e) - psi3(d)) / (2 * e), 2e-2);
    }
}
}  // namespace
