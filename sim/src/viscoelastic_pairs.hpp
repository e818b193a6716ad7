// The viscoelastic solver's pair passes (viscosity, density, relaxation displacement) for one
// particle at a time, compiled once per x86-64 level (viscoelastic_pairs_base.cpp and
// viscoelastic_pairs_avx2.cpp; the kernels are in viscoelastic_pairs_impl.hpp). Every level
// gives bit-identical results, so the level never changes a simulation.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace frnn::sim::detail {

/// What the pair passes read: particle arrays in cell order, D values per particle.
struct pair_view {
    const float* x = nullptr;
    const float* v = nullptr;
    const float* pressure = nullptr;       // p_i, one per particle
    const float* near_pressure = nullptr;  // the near pressures
    const float* box = nullptr;            // periodic box lengths per axis (0: open axis), or null
    float h = 0;                           // interaction radius
};

struct viscosity_coefficients {
    float dt = 0, sigma = 0, beta = 0;
};

/// A particle's neighbors [begin, end) and its index i.
struct pair_row {
    std::size_t i;
    const std::uint32_t* begin;
    const std::uint32_t* end;
};

template <int D>
struct viscoelastic_pair_kernels {
    /// The velocity change of particle i from the viscosity impulses of its approaching pairs.
    void (*viscosity)(const pair_view&, const pair_row&, const viscosity_coefficients&, float* dv);
    /// Density sum (1 - q)^2 and near density sum (1 - q)^3 over the neighbors closer than h.
    void (*density)(const pair_view&, const pair_row&, float* rho, float* rho_near);
    /// The relaxation displacement of particle i.
    void (*displacement)(const pair_view&, const pair_row&, float* dx);
};

namespace base {
template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs();
}
namespace avx2 {
template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs();
}

/// The kernels of the widest level this CPU and build run (frnn::simd_level(): FRNN_SIMD caps
/// it), or of the named level ("base", "avx2") when that is given and available.
template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs_for(std::string_view level = {});

}  // namespace frnn::sim::detail
