// The WCSPH pair passes of sph_pairs.hpp, for the level of namespace FRNN_SIM_NS. Included by
// one source file per level after all other headers.
//
// The cubic spline with support R is W(r) = norm w(q), q = r / R, w = 6 (q^3 - q^2) + 1 for
// q <= 1/2 and 2 (1 - q)^3 for q < 1 (kernels.hpp), and dW/dr = 6 norm / R g(q), g = 3 q^2 - 2 q
// and -(1 - q)^2 on the two pieces. The passes sum w and g without the constant factors, which
// the solver applies once per particle; both pieces are computed and one selected per lane.
#include "neighbor_lanes.hpp"

namespace frnn::sim::detail::FRNN_SIM_NS {

/// w(q) for q < 1, else 0.
inline lanes spline(lanes q) {
    const lanes t = 1 - q;
    const lanes inner = 6 * (q * q * q - q * q) + 1, outer = 2 * t * t * t;
    return select(q < 1, blend(q <= 0.5f, inner, outer));
}

/// g(q) (both pieces; the caller clears q >= 1).
inline lanes spline_slope(lanes q) {
    const lanes t = 1 - q;
    return blend(q <= 0.5f, 3 * q * q - 2 * q, -(t * t));
}

template <int D>
void density(const sph_view& s, const sph_row& row, float* fluid_out, float* walls_out) {
    const std::size_t i = row.i;
    const float inv_r = 1 / s.support, far = 2 * s.support, *x_i = s.position + 4 * i;
    lanes fluid = lanes{}, walls = lanes{};
    for_each_record_block<D>(s.position, x_i, i, s.box, row.begin, row.end, far,
                             [&](const record_block<D>& b) { fluid += spline(sqrt_lanes(b.r2) * inv_r); });
    if (row.wall_begin < row.wall_end)
        for_each_record_block<D>(s.wall, x_i, *row.wall_begin, nullptr, row.wall_begin, row.wall_end, far,
                                 [&](const record_block<D>& b) { walls += spline(sqrt_lanes(b.r2) * inv_r) * b.extra; });
    *fluid_out = sum_lanes(fluid);
    *walls_out = sum_lanes(walls);
}

// Per pair (r = x_j - x_i, len = |r|, v_ij . x_ij = -(v_i - v_j) . r) the pressure and
// artificial viscosity term (P_i + P_j + c min(v_ij . x_ij, 0) / ((len^2 + eps2)(rho_i + rho_j)))
// g / len r, P = p / rho^2, c = -2 alpha c0 h, written over one division; with the laminar
// viscosity (1/rho_i + 1/rho_j) g len / (len^2 + eps2) (v_i - v_j); with the background
// pressure (1/rho_i^2 + 1/rho_j^2) g / len r. The wall particles are at rest; the artificial
// viscosity against them has its own c (0 for free slip).
template <int D>
void forces(const sph_view& s, const sph_row& row, float* acc_out, float* laminar_out, float* background_out) {
    const std::size_t i = row.i;
    const float R = s.support, inv_r = 1 / R, far = 2 * R, eps2 = s.eps2, c = s.viscosity, c_wall = s.wall_viscosity;
    const float *x_i = s.position + 4 * i, *v_i = s.velocity + 4 * i;
    const float rho_i = x_i[3], p_i = v_i[3];
    lanes acc[D] = {}, laminar[D] = {}, background[D] = {};
    const bool with_laminar = s.laminar > 0, with_background = s.background > 0;
    for_each_record_block<D>(s.position, x_i, i, s.box, row.begin, row.end, far, [&](const record_block<D>& b) {
        const lanes len = sqrt_lanes(b.r2), q = len * inv_r;
        const lane_mask close = (len > 0) & (q < 1);
        const lanes g = spline_slope(q);
        lanes v_j[4];
        b.read(s.velocity, v_j);
        lanes dv[D], vr = lanes{};
        for (int a = 0; a < D; ++a) dv[a] = v_i[a] - v_j[a], vr -= dv[a] * b.r[a];
        const lanes rho_j = b.extra, d2 = b.r2 + eps2;
        const lanes den = d2 * (rho_i + rho_j);
        const lanes num = (p_i + v_j[3]) * den + c * blend(vr < 0, vr, lanes{});
        const lanes term = select(close, num * g / (len * den));
        for (int a = 0; a < D; ++a) acc[a] += term * b.r[a];
        if (with_laminar) {
            const lanes k = select(close, (rho_i + rho_j) * g * len / (rho_i * rho_j * d2));
            for (int a = 0; a < D; ++a) laminar[a] += k * dv[a];
        }
        if (with_background) {
            const float inv_i = 1 / (rho_i * rho_i);
            const lanes k = select(close, (inv_i + 1 / (rho_j * rho_j)) * g / len);
            for (int a = 0; a < D; ++a) background[a] += k * b.r[a];
        }
    });
    if (row.wall_begin < row.wall_end)
        for_each_record_block<D>(s.wall, x_i, *row.wall_begin, nullptr, row.wall_begin, row.wall_end, far,
                                 [&](const record_block<D>& b) {
                                     const lanes len = sqrt_lanes(b.r2), q = len * inv_r;
                                     const lane_mask close = (len > 0) & (q < 1);
                                     const lanes g = spline_slope(q);
                                     lanes vr = lanes{};
                                     for (int a = 0; a < D; ++a) vr -= v_i[a] * b.r[a];
                                     lanes p_w;
                                     for (int l = 0; l < lane_count; ++l) p_w[l] = s.wall_p_over_rho2[b.j[l]];
                                     const lanes den = (b.r2 + eps2) * (rho_i + b.extra);
                                     const lanes num = (p_i + p_w) * den + c_wall * blend(vr < 0, vr, lanes{});
                                     const lanes term = select(close, num * g / (len * den));
                                     for (int a = 0; a < D; ++a) acc[a] += term * b.r[a];
                                 });
    for (int a = 0; a < D; ++a) {
        acc_out[a] = sum_lanes(acc[a]);
        laminar_out[a] = sum_lanes(laminar[a]);
        background_out[a] = sum_lanes(background[a]);
    }
}

// With the continuity equation, d rho_i / dt = m dW/dr sum_j V_j g (rho_i vr / len -
// k (rho_j - rho_i) len / (len^2 + eps2)), k = 2 delta h c0: Antuono et al.'s (2010)
// rho_i sum_j V_j v_ij . grad_i W plus Molteni and Colagrossi's (2009) density diffusion
// k sum_j V_j (rho_j - rho_i) x_ji . grad_i W / (len^2 + eps2), as grad_i W = -dW/dr r / len
// (so x_ji . grad_i W = -dW/dr len > 0: density flows from the denser particle). The volume
// V_j over m is 1 / rho_j for the fluid and 1 / rho0 for a wall particle (mass m rho_w / rho0,
// at rest).
template <int D>
float density_rate(const sph_view& s, const sph_row& row) {
    const std::size_t i = row.i;
    const float inv_r = 1 / s.support, far = 2 * s.support, eps2 = s.eps2, k = s.diffusion;
    const float *x_i = s.position + 4 * i, *v_i = s.velocity + 4 * i;
    const float rho_i = x_i[3];
    lanes rate = lanes{};
    for_each_record_block<D>(s.position, x_i, i, s.box, row.begin, row.end, far, [&](const record_block<D>& b) {
        const lanes len = sqrt_lanes(b.r2), q = len * inv_r;
        const lane_mask close = (len > 0) & (q < 1);
        lanes v_j[4];
        b.read(s.velocity, v_j);
        lanes vr = lanes{};
        for (int a = 0; a < D; ++a) vr -= (v_i[a] - v_j[a]) * b.r[a];
        const lanes rho_j = b.extra;
        const lanes pair = rho_i * vr / len - k * (rho_j - rho_i) * len / (b.r2 + eps2);
        rate += select(close, spline_slope(q) / rho_j * pair);
    });
    if (row.wall_begin < row.wall_end)
        for_each_record_block<D>(s.wall, x_i, *row.wall_begin, nullptr, row.wall_begin, row.wall_end, far,
                                 [&](const record_block<D>& b) {
                                     const lanes len = sqrt_lanes(b.r2), q = len * inv_r;
                                     const lane_mask close = (len > 0) & (q < 1);
                                     lanes vr = lanes{};
                                     for (int a = 0; a < D; ++a) vr -= v_i[a] * b.r[a];
                                     const lanes pair = rho_i * vr / len - k * (b.extra - rho_i) * len / (b.r2 + eps2);
                                     rate += select(close, spline_slope(q) * s.inv_rest_density * pair);
                                 });
    return sum_lanes(rate);
}

template <int D>
wall_sums extrapolation(const sph_view& s, std::size_t w, const std::uint32_t* begin, const std::uint32_t* end,
                        const float* gravity) {
    const float inv_r = 1 / s.support, far = 2 * s.support;
    lanes weight = lanes{}, pressure = lanes{}, rise = lanes{};
    if (begin < end)
        for_each_record_block<D>(s.position, s.wall + 4 * w, *begin, nullptr, begin, end, far,
                                 [&](const record_block<D>& b) {
                                     const lanes k = spline(sqrt_lanes(b.r2) * inv_r);
                                     lanes down = lanes{};  // g . (x_f - x_w)
                                     for (int a = 0; a < D; ++a) down += gravity[a] * b.r[a];
                                     lanes p;
                                     for (int l = 0; l < lane_count; ++l) p[l] = s.pressure[b.j[l]];
                                     weight += k;
                                     pressure += p * k;
                                     rise -= down * b.extra * k;
                                 });
    return {sum_lanes(weight), sum_lanes(pressure), sum_lanes(rise)};
}

template <int D>
sph_pair_kernels<D> sph_pairs() {
    return {&density<D>, &forces<D>, &density_rate<D>, &extrapolation<D>};
}
template sph_pair_kernels<2> sph_pairs<2>();
template sph_pair_kernels<3> sph_pairs<3>();

}  // namespace frnn::sim::detail::FRNN_SIM_NS
