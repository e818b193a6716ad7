// The rows of the solver parameter table. The parser ranges are those the scene files always
// accepted; the panel ranges were chosen so that 100 steps at either end of each stay finite
// on the shipped scenes (tests/sim/parameters_test.cpp runs them).
#include "frnn/sim/parameters.hpp"

#include <cmath>
#include <sstream>

#include "frnn/error.hpp"

namespace frnn::sim {
namespace {

constexpr double unbounded = 1e300;

// The text fields, built as strings and moved in (GCC 12 misreports assigning short literals
// to a string's inline buffer as an overlapping copy, -Wrestrict, bug 105651).
parameter named(std::string section, std::string key, std::string unit, std::string help) {
    parameter p;
    p.section = std::move(section);
    p.key = std::move(key);
    p.unit = std::move(unit);
    p.help = std::move(help);
    return p;
}

template <class Params, class Field>
parameter real(const char* section, Params scene::*params, Field Params::*field, const char* key, const char* unit,
               double min, double max, double ui_min, double ui_max, bool live, const char* help, bool log_scale = false) {
    parameter p = named(section, key, unit, help);
    p.kind = parameter_kind::real;
    p.min = min, p.max = max, p.ui_min = ui_min, p.ui_max = ui_max;
    p.log_scale = log_scale;
    p.live = live;
    p.get = [params, field](const scene& s) { return double(s.*params.*field); };
    p.set = [params, field](scene& s, double v) { s.*params.*field = v; };
    return p;
}

template <class Params>
parameter boolean(const char* section, Params scene::*params, bool Params::*field, const char* key, bool live,
                  const char* help) {
    parameter p = named(section, key, "1", help);
    p.kind = parameter_kind::boolean;
    p.min = p.ui_min = 0;
    p.max = p.ui_max = 1;
    p.live = live;
    p.get = [params, field](const scene& s) { return s.*params.*field ? 1.0 : 0.0; };
    p.set = [params, field](scene& s, double v) { s.*params.*field = v != 0; };
    return p;
}

template <class Params, class Enum>
parameter choice(const char* section, Params scene::*params, Enum Params::*field, const char* key,
                 std::vector<std::string> names, bool live, const char* help) {
    parameter p = named(section, key, "1", help);
    p.kind = parameter_kind::choice;
    p.min = p.ui_min = 0;
    p.max = p.ui_max = double(names.size() - 1);
    p.choices = std::move(names);
    p.live = live;
    p.get = [params, field](const scene& s) { return double(static_cast<int>(s.*params.*field)); };
    p.set = [params, field](scene& s, double v) { s.*params.*field = static_cast<Enum>(int(v)); };
    return p;
}

std::vector<parameter> make_table() {
    const char* ve = "viscoelastic";
    const char* sp = "sph";
    using vp = viscoelastic_params;
    using spp = sph_params;
    const auto V = &scene::viscoelastic;
    const auto S = &scene::sph;
    return {
        real(ve, V, &vp::h_ratio, "h_ratio", "1", 1, 4, 1.5, 2.5, false, "interaction radius h in particle spacings"),
        real(ve, V, &vp::dt, "dt", "s", 1e-7, 1, 1e-4, 0.01, true, "largest time step", true),
        real(ve, V, &vp::cfl, "cfl", "1", 0, 1, 0.05, 0.5, true, "dt <= cfl h / max speed (0: fixed dt)"),
        real(ve, V, &vp::stiffness, "stiffness", "1", 0, unbounded, 0.01, 0.2, true, "pressure stiffness k"),
        real(ve, V, &vp::near_stiffness, "near_stiffness", "1", 0, unbounded, 0.01, 1, true, "near-pressure stiffness k_near"),
        real(ve, V, &vp::rest_density, "rest_density", "1", 0, unbounded, 0, 5, false,
             "kernel sum at rest (0: that of the initial lattice)"),
        real(ve, V, &vp::sigma, "sigma", "1/s", 0, unbounded, 0, 5, true, "linear viscosity"),
        real(ve, V, &vp::beta, "beta", "s/m", 0, unbounded, 0, 1, true, "quadratic viscosity"),
        boolean(ve, V, &vp::springs, "springs", false, "elasticity with plasticity"),
        real(ve, V, &vp::spring_stiffness, "spring_stiffness", "1", 0, 1, 0, 0.3, true, "fraction of (L - r) corrected per step"),
        real(ve, V, &vp::yield_ratio, "yield_ratio", "1", 0, unbounded, 0, 0.5, true, "stretch before a spring yields"),
        real(ve, V, &vp::plasticity, "plasticity", "1/s", 0, unbounded, 0, 1, true, "rate of plastic flow"),

        real(sp, S, &spp::h_ratio, "h_ratio", "1", 0.5, 2.5, 1, 1.5, false, "smoothing length h in particle spacings"),
        choice(sp, S, &spp::eos, "eos", {"tait", "ideal"}, true, "equation of state"),
        real(sp, S, &spp::rest_density, "rest_density", "kg/m^3", 1e-9, unbounded, 500, 2000, false, "rest density (sets the mass)"),
        real(sp, S, &spp::sound_speed, "sound_speed", "m/s", 0, unbounded, 0, 100, false,
             "speed of sound (0: 10 sqrt(2 g H))"),
        real(sp, S, &spp::gamma, "gamma", "1", 1, 10, 1, 10, true, "Tait exponent"),
        choice(sp, S, &spp::viscosity, "viscosity", {"artificial", "laminar"}, true,
               "artificial (alpha) or laminar (nu, Morris et al. 1997)"),
        real(sp, S, &spp::alpha, "alpha", "1", 0, 10, 0, 1, true, "artificial viscosity"),
        real(sp, S, &spp::nu, "nu", "m^2/s", 0, unbounded, 0, 0.05, true, "kinematic viscosity (laminar)"),
        choice(sp, S, &spp::integrator, "integrator", {"symplectic-euler", "leapfrog"}, false, "time integrator"),
        real(sp, S, &spp::cfl, "cfl", "1", 1e-3, 1, 0.05, 0.5, true, "dt <= cfl h / (c0 + max speed)"),
        real(sp, S, &spp::max_dt, "max_dt", "s", 1e-9, 1, 1e-5, 1e-3, true, "largest time step", true),
        boolean(sp, S, &spp::clamp_negative_pressure, "clamp_negative_pressure", true, "no tension: p >= 0"),
        boolean(sp, S, &spp::wall_density, "wall_density", true, "colliders add to the density"),
        boolean(sp, S, &spp::wall_particles, "wall_particles", false,
                "static colliders as wall particles with extrapolated pressure"),
        boolean(sp, S, &spp::free_slip, "free_slip", false, "no artificial viscosity against the wall particles"),
        real(sp, S, &spp::background_pressure, "background_pressure", "Pa", 0, unbounded, 0, 1e6, false,
             "transport velocity's background pressure (0: off; no free surface)"),
        real(sp, S, &spp::settle_time, "settle_time", "s", 0, unbounded, 0, 1, false,
             "damp the velocities for this long from the start (settling)"),
        choice(sp, S, &spp::density, "density", {"summation", "continuity"}, false,
               "kernel sum, or the continuity equation with density diffusion"),
        real(sp, S, &spp::density_diffusion, "density_diffusion", "1", 0, 1, 0, 0.5, true,
             "density diffusion delta (continuity; Molteni & Colagrossi 2009)"),
        real(sp, S, &spp::bulk_viscosity, "bulk_viscosity", "1", 0, 2, 0, 1, true,
             "bulk viscosity zeta / (h c0): damps compression only (0: off)"),
        boolean(sp, S, &spp::wall_friction, "wall_friction", true, "walls' shear stress by the log law (nu)"),
    };
}

}  // namespace

const std::vector<parameter>& parameters() {
    static const std::vector<parameter> table = make_table();
    return table;
}

const parameter* find_parameter(std::string_view name) {
    const auto dot = name.find('.');
    if (dot == std::string_view::npos) return nullptr;
    for (const auto& p : parameters())
        if (name.substr(0, dot) == p.section && name.substr(dot + 1) == p.key) return &p;
    return nullptr;
}

void check_parameter_value(const parameter& p, double value) {
    const bool whole = p.kind == parameter_kind::real || value == std::floor(value);
    if (std::isfinite(value) && value >= p.min && value <= p.max && whole) return;
    std::ostringstream m;
    m << "parameter " << p.name() << ": expected ";
    if (p.kind == parameter_kind::real) m << "a number in [" << p.min << ", " << p.max << "]";
    else if (p.kind == parameter_kind::boolean) m << "0 or 1";
    else m << "an index from 0 to " << p.choices.size() - 1;
    m << ", got " << value;
    throw error(m.str());
}

std::string parameter_section(solver_kind k) { return k == solver_kind::sph ? "sph" : "viscoelastic"; }

}  // namespace frnn::sim
