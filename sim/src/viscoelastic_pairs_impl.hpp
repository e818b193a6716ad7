// The viscoelastic pair passes of viscoelastic_pairs.hpp, for the level of namespace
// FRNN_SIM_NS; the physics is described in viscoelastic.cpp. Included by one source file per
// level after all other headers.
#include "neighbor_lanes.hpp"

namespace frnn::sim::detail::FRNN_SIM_NS {

template <int D>
void viscosity(const pair_view& s, const pair_row& row, const viscosity_coefficients& c, float* dv_out) {
    const std::size_t i = row.i;
    const float h = s.h, inv_h = 1 / h;
    lanes dv[D] = {};
    for_each_neighbor_block<D>(s.x, s.box, i, row.begin, row.end, 2 * h, [&](const neighbor_block<D>& b) {
        const lanes len = sqrt_lanes(b.r2);
        const lane_mask close = (len < h) & (len > 0);
        const lanes inv_len = 1 / len, q = len * inv_h;
        lanes u = lanes{};  // (v_i - v_j) . r
        for (int a = 0; a < D; ++a) u -= (b.gather(s.v, D, a) - s.v[i * D + a]) * b.r[a];
        // Only approaching pairs (u > 0) feel the impulse.
        u = u * inv_len;
        u = select(u > 0, u);
        const lanes imp = select(close, 0.5f * c.dt * (1 - q) * (c.sigma * u + c.beta * u * u) * inv_len);
        for (int a = 0; a < D; ++a) dv[a] -= imp * b.r[a];
    });
    for (int a = 0; a < D; ++a) dv_out[a] = sum_lanes(dv[a]);
}

template <int D>
void density(const pair_view& s, const pair_row& row, float* rho_out, float* rho_near_out) {
    const float h = s.h, inv_h = 1 / h;
    lanes rho = lanes{}, rho_near = lanes{};
    for_each_neighbor_block<D>(s.x, s.box, row.i, row.begin, row.end, 2 * h, [&](const neighbor_block<D>& b) {
        const lanes q = sqrt_lanes(b.r2) * inv_h;
        const lanes w = select(q < 1, (1 - q) * (1 - q));
        rho += w;
        rho_near += w * (1 - q);
    });
    *rho_out = sum_lanes(rho);
    *rho_near_out = sum_lanes(rho_near);
}

template <int D>
void displacement(const pair_view& s, const pair_row& row, float* dx_out) {
    const std::size_t i = row.i;
    const float h = s.h, inv_h = 1 / h;
    const float p_i = s.pressure[i], near_i = s.near_pressure[i];
    lanes dx[D] = {};
    for_each_neighbor_block<D>(s.x, s.box, i, row.begin, row.end, 2 * h, [&](const neighbor_block<D>& b) {
        const lanes len = sqrt_lanes(b.r2);
        const lane_mask close = (len < h) & (len > 0);
        const lanes inv_len = 1 / len, w = 1 - len * inv_h;
        const lanes p = p_i + b.gather(s.pressure, 1, 0), near = near_i + b.gather(s.near_pressure, 1, 0);
        const lanes mag = select(close, 0.5f * h * (p * w + near * w * w) * inv_len);
        for (int a = 0; a < D; ++a) dx[a] -= mag * b.r[a];
    });
    for (int a = 0; a < D; ++a) dx_out[a] = sum_lanes(dx[a]);
}

template <int D>
viscoelastic_pair_kernels<D> viscoelastic_pairs() {
    return {&viscosity<D>, &density<D>, &displacement<D>};
}
template viscoelastic_pair_kernels<2> viscoelastic_pairs<2>();
template viscoelastic_pair_kernels<3> viscoelastic_pairs<3>();

}  // namespace frnn::sim::detail::FRNN_SIM_NS
