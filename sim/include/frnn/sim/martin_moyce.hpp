// The dam-break reference: Martin and Moyce's (1952) measured surge front of a liquid column
// of width a and height 2a (sim/data/martin-moyce-1952.csv, compiled in), and a simulated
// front's error against it.
#pragma once
#include <utility>
#include <vector>

namespace frnn::sim {

/// One measured series: the column width in inches and its points (T, Z), T = t sqrt(2 g / a)
/// increasing, Z = front / a.
struct front_series {
    double a_inches = 0;
    std::vector<std::pair<double, double>> points;
};

/// Both series of the paper's Figure 3, a = 1.125 in and a = 2.25 in, in that order.
const std::vector<front_series>& martin_moyce();

/// The T range the error is taken over: past the first instants, which the experiment's gate
/// delayed, and before the front reaches the end of a tank 8a long (T about 3.2 in frnn's scene).
inline constexpr double front_error_t_lo = 0.5, front_error_t_hi = 3.0;

/// Mean over the series' points with T in [t_lo, t_hi] of |Z_sim - Z| / Z, Z_sim linearly
/// interpolated in `front` (sorted by T). Throws frnn::error when `front` does not cover those
/// points or there are none.
double front_error(const std::vector<std::pair<double, double>>& front, const front_series& series,
                   double t_lo = front_error_t_lo, double t_hi = front_error_t_hi);

/// The self-convergence measure D(coarse, fine): the mean of |Z_coarse - Z_fine| / Z_fine over
/// T = t_lo, t_lo + 0.02, ..., t_hi, both fronts (sorted by T) interpolated linearly. Throws
/// frnn::error when either does not cover [t_lo, t_hi].
double front_difference(const std::vector<std::pair<double, double>>& coarse,
                        const std::vector<std::pair<double, double>>& fine, double t_lo = front_error_t_lo,
                        double t_hi = front_error_t_hi);

/// The signed relative error (Z_sim - Z) / Z at each of the series' points with T in [t_lo,
/// t_hi], as (T, error) pairs: positive where the simulated front leads. Throws as front_error.
std::vector<std::pair<double, double>> signed_front_errors(const std::vector<std::pair<double, double>>& front,
                                                           const front_series& series, double t_lo = front_error_t_lo,
                                                           double t_hi = front_error_t_hi);

/// Richardson's extrapolation to zero spacing of the fronts at spacings h (coarse) and h/2
/// (fine) converging with order p: Z_fine + (Z_fine - Z_coarse) / (2^p - 1) at T = t_lo,
/// t_lo + 0.02, ..., t_hi. Throws frnn::error when p is not positive or a front does not
/// cover [t_lo, t_hi].
std::vector<std::pair<double, double>> richardson_front(const std::vector<std::pair<double, double>>& coarse,
                                                        const std::vector<std::pair<double, double>>& fine, double p,
                                                        double t_lo = front_error_t_lo,
                                                        double t_hi = front_error_t_hi);

}  // namespace frnn::sim
