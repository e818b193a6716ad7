// Scenes of the particle-fluid simulation: fluid blocks, colliders, solver parameters and
// output settings, read from JSON (the shipped scenes live in sim/scenes/ and are compiled into
// the library, so `--scene dam-break` works from any directory).
//
// Every vector has three components; a 2D run drops z. A bad scene throws frnn::error naming
// the file, the key (as a path such as `colliders[2].half`) and what was expected.
// Thread safety: plain values; the functions are reentrant.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "frnn/sim/colliders.hpp"

namespace frnn::sim {

enum class solver_kind { viscoelastic, sph };
std::string to_string(solver_kind k);

/// The names scene files give solvers, fluid block types and collider types, in the order of
/// their enums (solver_kind, fluid_block::kind_t, shape); the parser accepts these and no other.
const std::vector<std::string>& solver_names();
const std::vector<std::string>& fluid_block_types();
const std::vector<std::string>& collider_types();

/// A region filled with particles on a lattice of the scene's spacing.
struct fluid_block {
    enum class kind_t { box, sphere } kind = kind_t::box;
    vec3 min{0, 0, 0}, max{1, 1, 1};  ///< box
    vec3 center{0, 0, 0};             ///< sphere
    double radius = 0.5;
    vec3 velocity{0, 0, 0};           ///< initial velocity
    /// Each coordinate moved off the lattice by up to jitter lattice steps, uniform and the same
    /// in every run (a hash of the block and lattice indices); 0 to 0.5, 0 = the lattice.
    double jitter = 0;
};

/// Clavet et al. 2005. Stiffnesses are dimensionless: one relaxation moves a particle by
/// h * stiffness * (rho - rho0) / rho0 * (1 - q) per neighbor (the dt^2 k of the paper), so the
/// behaviour does not change with resolution. sigma [1/s] and beta [s/m] as in the paper.
struct viscoelastic_params {
    double h_ratio = 2.0;        ///< interaction radius h = h_ratio * particle spacing
    double dt = 0.004;           ///< time step [s] (the largest, with cfl > 0)
    double cfl = 0.25;           ///< > 0: dt <= cfl * h / max speed (0.6 cfl in 2D)
    double stiffness = 0.1;      ///< pressure (k)
    double near_stiffness = 0.2; ///< near pressure (k_near)
    double rest_density = 0;     ///< 0: the density of the initial lattice
    double sigma = 0, beta = 0.2;
    bool springs = false;        ///< elasticity with plasticity
    double spring_stiffness = 0.05; ///< dimensionless: fraction of (L - r) corrected per step
    double yield_ratio = 0.1, plasticity = 0.3;
};

/// Weakly compressible SPH (Becker and Teschner 2007 style) with the cubic spline kernel.
struct sph_params {
    double h_ratio = 1.2;          ///< smoothing length h = h_ratio * spacing (support 2h)
    enum class eos_t { tait, ideal } eos = eos_t::tait;
    double rest_density = 1000;    ///< [kg/m^3]
    double sound_speed = 0;        ///< 0: 10 * sqrt(2 g H), H the fluid's initial height
    double gamma = 7;              ///< Tait exponent
    /// The viscous term: Monaghan's artificial viscosity (alpha), or the laminar viscosity of
    /// Morris, Fox and Zhu (1997) with kinematic viscosity nu.
    enum class viscosity_t { artificial, laminar } viscosity = viscosity_t::artificial;
    double alpha = 0.05;           ///< Monaghan artificial viscosity (viscosity "artificial")
    double nu = 1e-6;              ///< kinematic viscosity [m^2/s] (viscosity "laminar"; water: 1e-6)
    enum class integrator_t { symplectic_euler, leapfrog } integrator = integrator_t::symplectic_euler;
    double cfl = 0.4;
    double max_dt = 1e-3;
    bool clamp_negative_pressure = true;
    bool wall_density = true;      ///< boundary integrals of the kernel over the colliders
    /// Static colliders as layers of wall particles whose pressure is extrapolated from the
    /// fluid (Adami, Hu and Adams 2012), instead of the kernel integrals (wall_density).
    bool wall_particles = false;
    /// With wall_particles: no artificial viscosity between the fluid and the wall particles,
    /// so the walls hold the fluid without friction (free slip; default: no slip).
    bool free_slip = false;
    /// > 0: particles move with the transport velocity of Adami, Hu and Adams (2013), pushed
    /// by this background pressure [Pa] towards a uniform spacing (0: off). For flows with no
    /// free surface (the background pressure pulls a free surface apart).
    double background_pressure = 0;
    /// > 0: for this long [s] from the start the velocities are damped at rate pi c0 / H
    /// (critical for the fluid's slowest sound wave, H the initial fluid height), so a fluid
    /// released at rest settles into equilibrium instead of ringing.
    double settle_time = 0;
    /// The density: the kernel sum over the neighbors (summation), or integrated in time by
    /// the continuity equation with the density diffusion of Molteni and Colagrossi (2009),
    /// strength density_diffusion (delta; 0.1 is the literature's value, 0: none).
    enum class density_t { summation, continuity } density = density_t::summation;
    double density_diffusion = 0.1;
    /// > 0: a bulk viscosity zeta = bulk_viscosity h c0 adds zeta d rho / dt to each
    /// particle's pressure (and so to the walls' extrapolated pressure): it damps compression,
    /// sound, and leaves a divergence-free flow alone (0: off).
    double bulk_viscosity = 0;
    /// The colliders' walls hold the fluid sliding along them back with the shear stress of a
    /// smooth wall's law (log law, with the kinematic viscosity nu), spread over the fluid
    /// within the kernel's reach of the wall (false: no such friction).
    bool wall_friction = false;
};

/// Records the surge front: Z = (max x + spacing/2 - origin) / a along `axis`, against
/// T = t sqrt(2 g / a), into front.csv.
struct front_probe {
    bool enabled = false;
    double a = 0.25, origin = 0;
    int axis = 0;
    double every_T = 0.02;
};

struct output_params {
    double fps = 60;              ///< frames per simulated second (used when every == 0)
    int every = 0;                ///< output every K steps (0: from fps)
    int checkpoint_every = 5;     ///< checkpoint every K frames
};

struct scene {
    std::string name = "scene";
    std::string description;
    solver_kind solver = solver_kind::viscoelastic;
    int dim = 3;
    std::size_t particles_2d = 4096, particles_3d = 32768;  ///< target counts
    double duration = 1.0;        ///< simulated seconds
    std::uint64_t steps = 0;      ///< > 0: run exactly this many steps instead
    vec3 gravity{0, -9.81, 0};
    vec3 domain_min{0, 0, 0}, domain_max{1, 1, 1};  ///< grid bounds and camera framing
    /// Periodic box lengths: particles live in [0, L) on each axis, wrapped, and pair vectors
    /// take the minimum image. A length of 0 leaves that axis open (a channel or a slab); all 0,
    /// the default, is an open domain.
    vec3 periodic{0, 0, 0};
    std::vector<fluid_block> fluid;
    std::vector<collider> colliders;
    viscoelastic_params viscoelastic;
    sph_params sph;
    front_probe front;
    output_params output;

    std::size_t target_particles() const { return dim == 2 ? particles_2d : particles_3d; }
    bool is_periodic() const { return periodic[0] > 0 || periodic[1] > 0 || periodic[2] > 0; }
};

/// Parses a scene; `origin` (a file name) prefixes error messages.
scene parse_scene(const std::string& json_text, const std::string& origin);
/// The scene as JSON that parse_scene reads back to an equal scene (numbers in shortest
/// round-trip form; collider angles in degrees, as in the files).
std::string scene_to_json(const scene& s);
/// Reads and parses a scene file.
scene load_scene(const std::string& path);
/// The scenes shipped in sim/scenes/ by name ("dam-break", "droplet", "block-drop").
scene builtin_scene(const std::string& name);
std::vector<std::string> builtin_scene_names();
/// JSON text of a shipped scene.
std::string builtin_scene_text(const std::string& name);

/// Command-line overrides, applied after parsing (and stored in checkpoints).
struct scene_overrides {
    std::optional<solver_kind> solver;
    std::optional<int> dim;
    std::optional<std::size_t> particles;
    std::optional<std::uint64_t> steps;
    std::optional<double> duration;
    std::optional<int> every;
};
/// Applies the overrides and, for dim 2, flattens colliders and vectors to the xy plane.
void apply(scene& s, const scene_overrides& o);

/// Initial particles on a lattice: positions (N * dim, interleaved) and velocities; the lattice
/// spacing is chosen so the count is close to the target. Throws when no particle fits.
struct seeded_particles {
    std::vector<float> x, v;
    double spacing = 0;
    std::size_t count = 0;
};
seeded_particles seed(const scene& s);

}  // namespace frnn::sim
