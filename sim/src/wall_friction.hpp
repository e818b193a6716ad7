// The friction of a smooth wall on a fluid sliding along it, by the law of the wall (Pope,
// "Turbulent Flows", 2000, section 7.1; the constants kappa = 0.41 and E = 9.8 are the usual
// ones of wall functions, e.g. Launder and Spalding 1974): a fluid moving at u at distance y
// from the wall, of kinematic viscosity nu, exerts the shear stress rho u_tau^2 on it, with the
// friction velocity u_tau from
//   u / u_tau = y u_tau / nu                   in the viscous sublayer (y+ = y u_tau / nu <= y+_c),
//   u / u_tau = ln(E y u_tau / nu) / kappa     in the log layer (y+ > y+_c),
// y+_c where the two meet (11.5), so u_tau is continuous in u and y.
#pragma once
#include <cmath>

namespace frnn::sim::detail {

constexpr double log_law_kappa = 0.41, log_law_e = 9.8;

/// y+ where the viscous sublayer's u+ = y+ meets the log law's u+ = ln(E y+) / kappa.
inline double log_law_crossover() {
    double y = 11;
    for (int it = 0; it < 60; ++it) y = std::log(log_law_e * y) / log_law_kappa;  // a contraction near 11.5
    return y;
}

/// u_tau of a fluid moving at u >= 0 at distance y > 0 from a smooth wall (nu > 0).
inline double friction_velocity(double u, double y, double nu) {
    if (!(u > 0)) return 0;
    static const double crossover = log_law_crossover();
    const double viscous = std::sqrt(nu * u / y);  // u+ = y+
    if (y * viscous / nu <= crossover) return viscous;
    // Newton on f(t) = kappa u / t - ln(E y t / nu), decreasing in t, from the viscous
    // estimate, which lies below the root (there f > 0): f is convex, so the iterates rise to
    // the root without overshooting it.
    double t = viscous;
    for (int it = 0; it < 50; ++it) {
        const double f = log_law_kappa * u / t - std::log(log_law_e * y * t / nu);
        const double slope = -log_law_kappa * u / (t * t) - 1 / t;
        const double next = t - f / slope;
        if (std::abs(next - t) <= 1e-15 * next) return next;
        t = next;
    }
    return t;
}

}  // namespace frnn::sim::detail
