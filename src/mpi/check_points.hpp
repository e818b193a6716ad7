// The checks of a rank's particles that every collective entry point makes before anything
// else: sizes, finite coordinates and weights, points inside the periodic box. Returns what is
// wrong (empty if nothing), for throw_if_any.
#pragma once
#include <cmath>
#include <span>
#include <string>

namespace frnn::mpi {

template <class T, int D>
std::string check_points(std::span<const T> coords, std::span<const double> periodic,
                         std::span<const double> weights = {}) {
    if (coords.size() % D != 0)
        return std::to_string(coords.size()) + " coordinates are not a multiple of " + std::to_string(D);
    if (!periodic.empty() && periodic.size() != std::size_t(D))
        return "periodic box needs " + std::to_string(D) + " lengths, got " + std::to_string(periodic.size());
    for (double length : periodic)
        if (!(length >= 0) || !std::isfinite(length))
            return "periodic box length " + std::to_string(length) + " must be finite and > 0 (or 0: an open axis)";
    const std::size_t n = coords.size() / D;
    if (!weights.empty() && weights.size() != n)
        return std::to_string(weights.size()) + " weights for " + std::to_string(n) + " particles";
    for (std::size_t i = 0; i < weights.size(); ++i)
        if (!(weights[i] >= 0) || !std::isfinite(weights[i]))
            return "particle " + std::to_string(i) + " has weight " + std::to_string(weights[i]) + " (must be finite, >= 0)";
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < D; ++a) {
            const double x = double(coords[i * D + std::size_t(a)]);
            if (!std::isfinite(x))
                return "particle " + std::to_string(i) + " has a non-finite coordinate on axis " + std::to_string(a);
            if (!periodic.empty() && periodic[std::size_t(a)] > 0 && !(x >= 0 && x < periodic[std::size_t(a)]))
                return "particle " + std::to_string(i) + " lies outside the periodic box [0, " +
                       std::to_string(periodic[std::size_t(a)]) + ") on axis " + std::to_string(a) + ": " + std::to_string(x);
        }
    return {};
}


}  // namespace frnn::mpi
