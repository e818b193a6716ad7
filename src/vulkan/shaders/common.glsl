// Shared by frnn's internal shaders: one thread per element, 2D dispatches past 65535 groups.
#ifndef FRNN_COMMON_GLSL
#define FRNN_COMMON_GLSL

#ifndef FRNN_GROUP_SIZE
#define FRNN_GROUP_SIZE 128
// Set when a loop ended before its condition did. lavapipe (Mesa's gallivm) silently stops
// every loop of an invocation group once they ran 65535 iterations in all; the host turns
// the flag into an error instead of returning a cut result.
#ifdef FRNN_STATUS_BINDING
layout(std430, binding = FRNN_STATUS_BINDING) buffer frnn_status_block { uint frnn_status; };
void frnn_loop_cut() { atomicOr(frnn_status, 1u); }
#endif

#endif

// Flat index of this invocation: groups are laid out x first, then y (the host splits large
// dispatches into rows of at most 65535 groups). A macro, not a function: gl_WorkGroupSize is
// only known after the shader's layout(local_size_x) declaration, which may come later.
#define frnn_thread_index() \
    (gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x)

uint frnn_group_index() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

// Saturating add: sums that overflow 32 bits stick at 0xFFFFFFFF, which the host reports as
// "too many pairs" instead of wrapping silently.
uint frnn_sat_add(uint a, uint b) {
    const uint s = a + b;
    return s < a ? 0xFFFFFFFFu : s;
}

#endif
