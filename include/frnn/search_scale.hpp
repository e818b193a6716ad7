// Extreme radii: the power of two by which a search is carried out so that no squared distance
// overflows or sinks into the subnormals, and the distance test that every backend and the
// brute-force oracle share.
//
// A search tests |x_i - x_j| <= r as d^2 <= r^2 in the input's precision T, with
// d^2 = (dx*dx + dy*dy) + dz*dz. When r^2 would overflow (r beyond about 2^62 in float, 2^510
// in double) or lose precision to underflow (r below about 2^-49, 2^-483), every coordinate,
// box length and the radius are first multiplied by s = search_scale(r, largest): multiplying
// by a power of two changes no rounding, so the answer is the one T would give with an
// unbounded exponent, and today's decisions at exact ties stay. For all other radii s = 1 and
// nothing is multiplied. Reported distances are divided by s again; squared distances too, and
// those that exceed T's range then read +infinity.
// Header-only, pure functions: safe from any thread.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>

#include "frnn/error.hpp"
#include "frnn/periodic_wrap.hpp"

namespace frnn {

/// The scale of a search with radius `radius` (finite, > 0) over coordinates and periodic box
/// lengths of magnitude at most `largest`: 1 for all but extreme radii (see above); otherwise
/// the power of two that brings r near 1, limited so that scaled coordinates stay below a
/// quarter of T's largest value (their differences then never overflow). Throws frnn::error
/// when that limit leaves r^2 subnormal: r is then below `largest` / 2^(about 1.5 * the
/// exponent range), beyond any grid's reach.
template <class T>
T search_scale(T radius, T largest) {
    using lim = std::numeric_limits<T>;
    // Exponents of r whose square is normal, with room to spare below, and finite with room
    // for the sum of three squares above.
    constexpr int low = (lim::min_exponent + lim::digits) / 2 + 1;  // float -49, double -483
    constexpr int high = lim::max_exponent / 2 - 2;                 // float 62, double 510
    const int e = std::ilogb(radius);
    if (e >= low && e <= high) return T(1);
    // s and 1/s must be values of T themselves: |k| < max_exponent.
    int k = std::clamp(-e, 1 - lim::max_exponent, lim::max_exponent - 1);
    if (largest > 0) k = std::min(k, lim::max_exponent - 3 - std::ilogb(largest));
    if (e + k < low) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "radius %.9g is too small for coordinates (or periodic box lengths) up to %.9g: "
                      "%s cannot square distances over that range",
                      double(radius), double(largest), sizeof(T) == 4 ? "float" : "double");
        throw error(text);
    }
    return std::ldexp(T(1), k);
}

/// What search_scale needs to know of a point set (values: interleaved coordinates, one per
/// axis of `periodic` when that is not empty): the largest magnitude of its coordinates on the
/// open axes and of the box lengths, which bound every coordinate of a periodic axis once
/// wrapped into the box (frnn/periodic_wrap.hpp), query points' too.
template <class T>
T largest_magnitude(std::span<const T> values, std::span<const double> periodic = {}) {
    T m = 0;
    for (std::size_t i = 0; i < values.size(); ++i)
        if (periodic.empty() || !(periodic[i % periodic.size()] > 0)) m = std::max(m, std::abs(values[i]));
    for (double b : periodic) m = std::max(m, T(std::min(b, double(std::numeric_limits<T>::max()))));
    return m;
}

/// A squared distance of the scaled search given back in the caller's units: (d2 / s) / s,
/// with inv = 1 / s (+infinity when beyond T's range).
template <class T>
T unscale_squared(T d2, T inv) {
    return d2 * inv * inv;
}

/// The distance test of a search with radius r and scale s: within(a, b) says whether the
/// points a and b (caller's coordinates) are neighbors and gives their squared distance in the
/// scaled units; `periodic` holds the box lengths (empty: open boundaries; 0: an open axis).
/// On a periodic axis both coordinates are wrapped into the box (in the caller's units) before
/// they are scaled, and the difference takes the minimum image.
template <class T, int D>
struct distance_test {
    T scale = 1, inv_scale = 1, r2 = 0;
    T box[D] = {};         ///< scaled box lengths (0 on an open axis)
    T caller_box[D] = {};  ///< the lengths in the caller's units, rounded to T
    bool periodic = false;

    distance_test(T radius, T s, std::span<const double> periodic_lengths = {})
        : scale(s), inv_scale(T(1) / s), periodic(!periodic_lengths.empty()) {
        if (periodic && periodic_lengths.size() != std::size_t(D))
            throw error("periodic box needs " + std::to_string(D) + " lengths, got " +
                        std::to_string(periodic_lengths.size()));
        const T r = radius * s;
        r2 = r * r;
        for (int a = 0; a < D && periodic; ++a) {
            caller_box[a] = T(periodic_lengths[std::size_t(a)]);
            box[a] = caller_box[a] * s;
        }
    }
    /// b - a on axis k in the scaled units (wrapped, minimum image on a periodic axis).
    T scaled_difference(const T* a, const T* b, int k) const {
        if (!periodic || !(box[k] > 0)) return b[k] * scale - a[k] * scale;
        const T d = wrap_into_box(b[k], caller_box[k]) * scale - wrap_into_box(a[k], caller_box[k]) * scale;
        return d - box[k] * std::nearbyint(d / box[k]);
    }
    /// Squared distance of a and b in the scaled units.
    T scaled_distance_squared(const T* a, const T* b) const {
        T d2 = 0;
        for (int k = 0; k < D; ++k) {
            const T d = scaled_difference(a, b, k);
            d2 += d * d;
        }
        return d2;
    }
    bool within(const T* a, const T* b, T& scaled_d2) const {
        scaled_d2 = scaled_distance_squared(a, b);
        return scaled_d2 <= r2;
    }
    /// The distance reported for a pair whose scaled squared distance is d2.
    T distance(T scaled_d2) const { return std::sqrt(scaled_d2) * inv_scale; }
    T distance_squared(T scaled_d2) const { return unscale_squared(scaled_d2, inv_scale); }
};

}  // namespace frnn
