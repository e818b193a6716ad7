// The color map of the particle fields: a perceptually ordered ramp from dark blue through
// teal and green to yellow (close to matplotlib's viridis), as linear pieces between stops, so
// the shader, the legend and the tests compute exactly the same colors.
#pragma once
#include <algorithm>
#include <array>

namespace frnn::view {

inline constexpr std::array<std::array<float, 3>, 6> colormap_stops = {{
    {0.267f, 0.005f, 0.329f},
    {0.254f, 0.265f, 0.530f},
    {0.164f, 0.471f, 0.558f},
    {0.134f, 0.659f, 0.518f},
    {0.478f, 0.821f, 0.318f},
    {0.993f, 0.906f, 0.144f},
}};

/// The color at t in [0, 1] (clamped).
inline std::array<float, 3> colormap(float t) {
    const float u = std::clamp(t, 0.f, 1.f) * float(colormap_stops.size() - 1);
    const std::size_t k = std::min(std::size_t(u), colormap_stops.size() - 2);
    const float f = u - float(k);
    std::array<float, 3> c{};
    for (int i = 0; i < 3; ++i) c[i] = colormap_stops[k][i] * (1 - f) + colormap_stops[k + 1][i] * f;
    return c;
}

}  // namespace frnn::view
