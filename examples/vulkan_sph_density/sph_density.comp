#version 450
// SPH density summation in a user shader: rho_i = sum_j m W(|x_i - x_j|, h) over the neighbors
// within h, the particle itself included, with the poly6 kernel W = 315/(64 pi h^9) (h^2 - d^2)^3.
// The grid's radius is h. Bindings 0-4: the grid (frnn/grid.glsl); 5: densities, caller's order.
#define FRNN_DIM 3
#include "frnn/grid.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 5) writeonly buffer density_block { float density[]; };
layout(push_constant) uniform push_block {
    float mass;
    float h;
} pc;

void main() {
    const uint s = frnn_invocation_index();
    if (s >= frnn_grid.count) return;
    const float h2 = pc.h * pc.h;
    const float poly6 = 315.0 / (64.0 * 3.14159265358979 * pow(pc.h, 9.0));
    float rho = 0.0;
    frnn_iterator it = frnn_begin(frnn_sorted_position(s));
    uint j;
    float d2;
    while (frnn_next(it, j, d2)) {
        const float w = h2 - d2;
        rho += w * w * w;
    }
    density[frnn_original_index(s)] = pc.mass * poly6 * rho;
}
