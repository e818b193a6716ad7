// frnn/sim/impact_pressure.hpp: the measured wall pressures read from their data file (sorted,
// on the right time axis, the features the case measures present), the figures on signals
// whose answers are known by hand, and the Shepard sensor on particles laid out by the test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/sim/impact_pressure.hpp"

using namespace frnn::sim;

namespace {

const pressure_series& series(const std::string& name) {
    for (const auto& s : impact_pressure_experiments())
        if (s.name == name) return s;
    throw frnn::error("no series " + name);
}

// A triangle: 0 up to T = 1, up to `height` at T = 2, back to 0 at T = 3, 0 up to T = 4.
pressure_signal triangle(double height) { return {{0, 0}, {1, 0}, {2, height}, {3, 0}, {4, 0}}; }

}  // namespace

TEST(ImpactPressure, DataHasFourSortedSeriesOnTheTimeAxisOfThePapers) {
    const auto& all = impact_pressure_experiments();
    ASSERT_EQ(all.size(), 4u);
    EXPECT_EQ(all[0].name, "buchner-60mm");
    EXPECT_DOUBLE_EQ(all[0].height, 0.2);
    EXPECT_DOUBLE_EQ(series("lobovsky-3mm").height, 0.003 / 0.3);
    EXPECT_DOUBLE_EQ(series("lobovsky-30mm").height, 0.03 / 0.3);
    EXPECT_DOUBLE_EQ(series("lobovsky-80mm").height, 0.08 / 0.3);
    // Ritter's ideal front, 2 sqrt(gH), crosses the 3.366H to the far wall at T = 1.68.
    const double ritter = (tank_length - column_length) / 2;
    for (const auto& s : all) {
        SCOPED_TRACE(s.name);
        ASSERT_GT(s.points.size(), 40u);
        for (std::size_t k = 1; k < s.points.size(); ++k) EXPECT_LE(s.points[k - 1].first, s.points[k].first);
        EXPECT_GE(s.points.front().first, 0);
        EXPECT_LE(s.points.back().first, 7.5);
        const double arrival = arrival_time(s.points);
        EXPECT_GT(arrival, ritter * 1.3);
        EXPECT_LT(arrival, 3.0);
    }
}

TEST(ImpactPressure, BuchnersFirstImpactIsAPlateauAndLobovskysLowestSensorASpike) {
    // Buchner: after the rise, the pressure holds between 0.5 and 0.7 rho g H until the
    // second impact (T about 5.5): no spike of the lowest sensor's kind.
    const pressure_signal& b = series("buchner-60mm").points;
    for (double T = 3.0; T <= 5.0; T += 0.1) {
        EXPECT_GT(running_mean(b, T), 0.5) << T;
        EXPECT_LT(running_mean(b, T), 0.7) << T;
    }
    EXPECT_LT(peak_mean(b, 2.5, 3.5), 0.75);
    // Sorting Buchner's times (digitised out of order) keeps every one of the file's points.
    EXPECT_EQ(b.size(), 86u);
    const pressure_signal& spike = series("lobovsky-3mm").points;
    double highest = 0;
    for (const auto& [T, P] : spike) highest = std::max(highest, P);
    EXPECT_GT(highest, 2.5);
    EXPECT_LT(pressure_at(spike, 3.5), 1.0);
}

TEST(ImpactPressure, ArrivalIsTheFirstCrossingInterpolated) {
    EXPECT_DOUBLE_EQ(arrival_time(triangle(1), 0.25), 1.25);
    EXPECT_DOUBLE_EQ(arrival_time(triangle(2), 0.25), 1.125);
    // A point exactly at the threshold is the arrival; a later, higher crossing is not.
    EXPECT_DOUBLE_EQ(arrival_time({{0, 0}, {1, 0.25}, {2, 0}, {3, 5}}, 0.25), 1.0);
    // Starting above: the first point.
    EXPECT_DOUBLE_EQ(arrival_time({{0.5, 1}, {1, 1}}, 0.25), 0.5);
    EXPECT_THROW(arrival_time(triangle(0.2), 0.25), frnn::error);
}

TEST(ImpactPressure, IntegralIsExactForThePiecewiseLinearSignal) {
    EXPECT_DOUBLE_EQ(pressure_integral(triangle(2), 0, 4), 2.0);  // the triangle's area
    // Bounds inside segments: from 1.5 (P = 1) to 2.5 (P = 1) via the apex 2.
    EXPECT_DOUBLE_EQ(pressure_integral(triangle(2), 1.5, 2.5), 1.5);
    EXPECT_DOUBLE_EQ(pressure_integral(triangle(2), 2.2, 2.2), 0.0);
    // A linear P = 1 + T sampled unevenly: the exact integral over [0.3, 2.9].
    const pressure_signal line = {{0, 1}, {0.1, 1.1}, {0.7, 1.7}, {0.75, 1.75}, {2, 3}, {3, 4}};
    EXPECT_NEAR(pressure_integral(line, 0.3, 2.9), (2.9 + 2.9 * 2.9 / 2) - (0.3 + 0.3 * 0.3 / 2), 1e-12);
    EXPECT_THROW(pressure_integral(line, -0.1, 1), frnn::error);
    EXPECT_THROW(pressure_integral(line, 1, 3.1), frnn::error);
}

TEST(ImpactPressure, PeakIsTheLargestRunningMean) {
    // At the apex of a triangle rising 2 per unit T, a window of 0.05 averages 2 - 0.025.
    EXPECT_NEAR(peak_mean(triangle(2), 0, 4, 0.05), 2 - 0.025, 1e-9);
    // Noise of +-0.3 on a plateau of 0.6, alternating faster than the window: the plateau.
    pressure_signal noisy;
    for (int k = 0; k <= 4000; ++k) noisy.emplace_back(k * 0.001, k < 1000 ? 0 : 0.6 + (k % 2 ? 0.3 : -0.3));
    EXPECT_NEAR(peak_mean(noisy, 1.2, 3.8, 0.05), 0.6, 0.01);
    // The window bounds where the peak is looked for: before the plateau there is none.
    EXPECT_DOUBLE_EQ(peak_mean(noisy, 0, 0.9, 0.05), 0.0);
    EXPECT_THROW(peak_mean(noisy, 1, 1.04, 0.05), frnn::error);
}

TEST(ImpactPressure, MeanErrorAndDifferenceAreInRhoGH) {
    pressure_signal sim, measured, shifted;
    for (int k = 0; k <= 600; ++k) {
        const double T = k * 0.01, P = T < 2 ? 0 : 0.5 + 0.1 * T;
        sim.emplace_back(T, P + 0.1);
        shifted.emplace_back(T, P - 0.2);
        if (k % 10 == 0) measured.emplace_back(T, P);
    }
    // Away from the step at T = 2 (which the running mean smooths) the offset is exact, against
    // the line through the measured points as against a signal sampled every step.
    EXPECT_NEAR(pressure_difference(sim, measured, 2.5, 5.5), 0.1, 1e-9);
    EXPECT_NEAR(pressure_difference(sim, shifted, 2.5, 5.5), 0.3, 1e-9);
    // Points outside the window do not count: an error there changes nothing.
    pressure_signal off = measured;
    off.front().second = 10;
    EXPECT_NEAR(pressure_difference(sim, off, 2.5, 5.5), 0.1, 1e-9);
    // A time average: points crowded on a spike weigh as long as the spike lasts. Ten points 5
    // above the line within 0.001 of T = 3 move the error by under 0.005 (a mean over the
    // measured points in the window would be 1.3).
    pressure_signal spiked;
    for (const auto& [T, P] : measured) {
        spiked.emplace_back(T, P);
        if (std::abs(T - 3) < 1e-9) {
            for (int k = 1; k <= 10; ++k) spiked.emplace_back(3 + k * 1e-4, P + 5);
            spiked.emplace_back(3.0011, P);
        }
    }
    EXPECT_NEAR(pressure_difference(sim, spiked, 2.5, 5.5), 0.1, 0.005);
    EXPECT_THROW(pressure_difference(sim, measured, 5.5, 6.1), frnn::error);
}

TEST(ImpactPressure, PressureDropIsSignedWhereTheDifferenceIsNot) {
    pressure_signal upper, lower, wavy;
    for (int k = 0; k <= 600; ++k) {
        const double T = k * 0.01, P = 0.5 + 0.1 * T;
        upper.emplace_back(T, P);
        lower.emplace_back(T, P + 0.25);
        wavy.emplace_back(T, P + 0.2 * std::sin(2 * 3.14159265358979 * T));  // whole periods over [2, 5]
    }
    EXPECT_NEAR(pressure_drop(lower, upper, 2, 5), 0.25, 1e-9);
    EXPECT_NEAR(pressure_drop(upper, lower, 2, 5), -0.25, 1e-9);
    // Above and below by turns: the drop averages out, the difference does not.
    EXPECT_NEAR(pressure_drop(wavy, upper, 2, 5), 0, 0.002);
    EXPECT_GT(pressure_difference(wavy, upper, 2, 5), 0.12);
    EXPECT_THROW(pressure_drop(lower, upper, 5.5, 6.1), frnn::error);
}

TEST(ImpactPressure, ShepardSensorAveragesTheFluidWithinTheSupport) {
    // A lattice 0.01 apart on x in [0, 1), y in [0, 0.5), pressure 100 + 2000 x + 500 y.
    std::vector<float> x, v, rho, p;
    std::vector<std::uint32_t> id;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 50; ++j) {
            const double px = 0.005 + 0.01 * i, py = 0.005 + 0.01 * j;
            x.push_back(float(px)), x.push_back(float(py));
            v.push_back(0), v.push_back(0), rho.push_back(1000);
            p.push_back(float(100 + 2000 * px + 500 * py));
            id.push_back(std::uint32_t(id.size()));
        }
    particle_view view;
    view.dim = 2, view.n = id.size(), view.x = x.data(), view.v = v.data(), view.rho = rho.data(), view.p = p.data(),
    view.id = id.data();
    // Inside, a symmetric neighborhood: the linear field's value at the point.
    EXPECT_NEAR(shepard_pressure(view, {0.5, 0.25, 0}, 0.026), 100 + 2000 * 0.5 + 500 * 0.25, 0.05);
    // On the wall x = 1: the fluid's side only, whose centre lies inside the fluid, so less
    // than the field continued to the wall, more than a spacing's worth inside.
    const double at_wall = shepard_pressure(view, {1.0, 0.25, 0}, 0.026);
    EXPECT_LT(at_wall, 100 + 2000 * 1.0 + 500 * 0.25);
    EXPECT_GT(at_wall, 100 + 2000 * (1.0 - 0.026) + 500 * 0.25);
    // No fluid within the support: 0.
    EXPECT_EQ(shepard_pressure(view, {1.03, 0.25, 0}, 0.026), 0.0);
    view.dim = 1;
    EXPECT_THROW(shepard_pressure(view, {0.5, 0.25, 0}, 0.026), frnn::error);
}

TEST(ImpactPressure, ShepardSensorAveragesInThreeDimensions) {
    // A lattice 0.01 apart on [0, 0.3) x [0, 0.2) x [0, 0.1), pressure 100 + 2000 x + 500 y + 300 z.
    std::vector<float> x, v, rho, p;
    std::vector<std::uint32_t> id;
    for (int i = 0; i < 30; ++i)
        for (int j = 0; j < 20; ++j)
            for (int k = 0; k < 10; ++k) {
                const double px = 0.005 + 0.01 * i, py = 0.005 + 0.01 * j, pz = 0.005 + 0.01 * k;
                x.push_back(float(px)), x.push_back(float(py)), x.push_back(float(pz));
                for (int a = 0; a < 3; ++a) v.push_back(0);
                rho.push_back(1000), p.push_back(float(100 + 2000 * px + 500 * py + 300 * pz));
                id.push_back(std::uint32_t(id.size()));
            }
    particle_view view;
    view.dim = 3, view.n = id.size(), view.x = x.data(), view.v = v.data(), view.rho = rho.data(), view.p = p.data(),
    view.id = id.data();
    const auto field = [](double px, double py, double pz) { return 100 + 2000 * px + 500 * py + 300 * pz; };
    EXPECT_NEAR(shepard_pressure(view, {0.15, 0.1, 0.05}, 0.026), field(0.15, 0.1, 0.05), 0.05);
    // The third coordinate counts: a point off the lattice's middle in z reads its own z.
    EXPECT_NEAR(shepard_pressure(view, {0.15, 0.1, 0.035}, 0.026), field(0.15, 0.1, 0.035), 0.05);
    // On the wall x = 0.3: the fluid's side only.
    const double at_wall = shepard_pressure(view, {0.3, 0.1, 0.05}, 0.026);
    EXPECT_LT(at_wall, field(0.3, 0.1, 0.05));
    EXPECT_GT(at_wall, field(0.3 - 0.026, 0.1, 0.05));
    EXPECT_EQ(shepard_pressure(view, {0.15, 0.1, 0.13}, 0.026), 0.0);
}
