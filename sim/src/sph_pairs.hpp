// The WCSPH solver's pair passes (density, forces, the wall particles' extrapolated pressure)
// for one particle at a time, compiled once per x86-64 level (sph_pairs_base.cpp and
// sph_pairs_avx2.cpp; the kernels are in sph_pairs_impl.hpp, the physics in sph.cpp and
// wall_particles.hpp). Each pair is computed in float, 8 neighbors at a time in the lanes of
// neighbor_lanes.hpp, without a branch per pair; a particle's sums depend on its neighbor lists
// alone, and every level gives bit-identical results, so neither the thread count nor the level
// changes a simulation.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace frnn::sim::detail {

/// What the WCSPH pair passes read: per particle in cell order, records of 4 floats (their
/// fourth float beside the D components, see neighbor_lanes.hpp), and the constants.
struct sph_view {
    const float* position = nullptr;  // fluid {x, rho}: the density pass reads x only
    const float* velocity = nullptr;  // fluid {v, p / rho^2}
    const float* pressure = nullptr;  // fluid p
    const float* box = nullptr;       // periodic box lengths per axis (0: open axis), or null
    const float* wall = nullptr;      // wall particles {x, rho}
    const float* wall_p_over_rho2 = nullptr;
    float support = 0;     // R = 2h
    float eps2 = 0;        // 0.01 h^2
    float viscosity = 0;   // the artificial viscosity's -2 alpha c0 h (0: off)
    float wall_viscosity = 0;  // the same against the wall particles (0: free slip)
    float laminar = 0;     // the laminar viscosity's nu (0: off)
    float background = 0;  // the transport velocity's background pressure p_b (0: off)
    float diffusion = 0;         // the density diffusion's 2 delta h c0 (0: off)
    float inv_rest_density = 0;  // 1 / rho0: a wall particle's volume over the mass m
};

/// A particle's neighbors among the fluid [begin, end) and among the walls [wall_begin, wall_end).
struct sph_row {
    std::size_t i;
    const std::uint32_t* begin;
    const std::uint32_t* end;
    const std::uint32_t* wall_begin;
    const std::uint32_t* wall_end;
};

/// Sums of a wall particle's fluid neighbors for its extrapolated pressure, with the kernel
/// w = W / norm (sph_pairs_impl.hpp; the factor cancels in the pressure).
struct wall_sums {
    float weight = 0;    // sum_f w_wf
    float pressure = 0;  // sum_f p_f w_wf
    float rise = 0;      // g . sum_f rho_f (x_w - x_f) w_wf
};

template <int D>
struct sph_pair_kernels {
    /// sum_j w_ij over the fluid neighbors and sum_w w_iw rho_w over the wall neighbors, with
    /// the kernel w = W / norm (sph_pairs_impl.hpp).
    void (*density)(const sph_view&, const sph_row&, float* fluid, float* walls);
    /// The momentum equation's sums over the fluid and wall neighbors without their constant
    /// factors (sph_pairs_impl.hpp): pressure and artificial viscosity into acc, the laminar
    /// viscosity into laminar and the background pressure into background (0 when off).
    void (*forces)(const sph_view&, const sph_row&, float* acc, float* laminar, float* background);
    /// The continuity equation's rate of density with the density diffusion, without its
    /// constant factor m dW/dr, over the fluid and wall neighbors (sph_pairs_impl.hpp).
    float (*density_rate)(const sph_view&, const sph_row&);
    /// The sums of wall particle w over its fluid neighbors [begin, end) (gravity: 3 values).
    wall_sums (*extrapolation)(const sph_view&, std::size_t w, const std::uint32_t* begin, const std::uint32_t* end,
                               const float* gravity);
};

namespace base {
template <int D>
sph_pair_kernels<D> sph_pairs();
}
namespace avx2 {
template <int D>
sph_pair_kernels<D> sph_pairs();
}

/// The kernels of the widest level this CPU and build run (frnn::simd_level(): FRNN_SIMD caps
/// it), or of the named level ("base", "avx2") when that is given and available.
template <int D>
sph_pair_kernels<D> sph_pairs_for(std::string_view level = {});

}  // namespace frnn::sim::detail
