// The wall-pressure reference of the 2D dam break: Buchner's (2002) and Lobovsky et al.'s
// (2014) measured pressures on the far wall of a tank 5.366H long, hit by a column 2H long
// and H high (sim/data/dam-break-pressure.csv, compiled in, with the citations), the pressure a
// simulation measures at a sensor, and the figures that compare two pressure signals.
//
// A signal is a list of points (T, P), T = t sqrt(g / H) sorted, P = p / (rho g H), read as
// the piecewise-linear function through them. Complexity: O(points) per call (peak_mean:
// O(points) per 1/20 of the width over the window). Thread safety: pure functions.
#pragma once
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "frnn/sim/solver.hpp"

namespace frnn::sim {

using pressure_signal = std::vector<std::pair<double, double>>;

/// One measured series: its name in the data file, the sensor's height over H, and its
/// points sorted by T (stably: points of equal T keep the file's order).
struct pressure_series {
    std::string name;
    double height = 0;
    pressure_signal points;
};

/// The four sensors, in this order: buchner-60mm (0.2H), lobovsky-3mm (0.01H), lobovsky-30mm
/// (0.1H), lobovsky-80mm (0.8H/3), H = 0.3 m.
const std::vector<pressure_series>& impact_pressure_experiments();

/// The tank (lengths over H): the column's length and height, the tank's length; the
/// sensors sit on the far wall, x = tank_length.
inline constexpr double column_length = 2.0, column_height = 1.0, tank_length = 5.366;
/// An impact arrives when P first reaches this (above the noise of Buchner's sensor before
/// impact, whose digitised points reach +-0.16).
inline constexpr double impact_threshold = 0.25;
/// The width in T of the running mean of the peak, the mean error and the self-convergence:
/// 8.8 ms for H = 0.3 m, so that a WCSPH signal's acoustic noise averages out.
inline constexpr double pressure_mean_width = 0.05;

/// P at T, linearly interpolated. Throws frnn::error when the signal does not cover T.
double pressure_at(const pressure_signal& s, double T);
/// The first T at which P reaches `threshold`, interpolated linearly between the point before
/// and the first point at or above it (the first point itself when it is). Throws
/// frnn::error when P never reaches it.
double arrival_time(const pressure_signal& s, double threshold = impact_threshold);
/// The integral of P over [t_lo, t_hi] (exact for the piecewise-linear signal). Throws
/// frnn::error when the signal does not cover the interval.
double pressure_integral(const pressure_signal& s, double t_lo, double t_hi);
/// The mean of P over [T - width/2, T + width/2].
double running_mean(const pressure_signal& s, double T, double width = pressure_mean_width);
/// The largest running mean (width `width`) over centres T = t_lo + width/2, ... in steps of
/// width/20, up to t_hi - width/2: the height of a peak or plateau in [t_lo, t_hi].
double peak_mean(const pressure_signal& s, double t_lo, double t_hi, double width = pressure_mean_width);
/// The mean over T = t_lo, t_lo + 0.01, ..., t_hi of |running_mean(a, T) - running_mean(b, T)|,
/// in rho g H: a time average, so that no stretch of a signal weighs more than another (a
/// digitised series holds its points densest on the impact's spike). Between two spacings it
/// is the self-convergence measure D(coarse, fine); between a simulated signal and a measured
/// series (the line through its points), the mean error after impact. Throws frnn::error
/// when a signal does not cover [t_lo - width/2, t_hi + width/2].
double pressure_difference(const pressure_signal& a, const pressure_signal& b, double t_lo, double t_hi);
/// The mean over the same grid of running_mean(lower, T) - running_mean(upper, T): how much
/// the pressure at a lower sensor exceeds that at an upper one, in rho g H. Water between them
/// gives (z_upper - z_lower) / H times (1 + its mean upward acceleration over g): their height
/// difference when it is at rest, 0 only when it falls freely. Throws as pressure_difference.
double pressure_drop(const pressure_signal& lower, const pressure_signal& upper, double t_lo, double t_hi);

/// The pressure a simulation measures at a point (its first dim coordinates count): the
/// Shepard (kernel-normalised) average sum_j p_j W(r_j) / sum_j W(r_j) over the fluid particles
/// within `support` of it, W the cubic spline of that support and dimension
/// (frnn/sim/kernels.hpp); 0 when none is. Wall particles do not count. Throws frnn::error when
/// the view is neither 2D nor 3D.
double shepard_pressure(const particle_view& v, const std::array<double, 3>& point, double support);

}  // namespace frnn::sim
