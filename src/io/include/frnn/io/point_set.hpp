// frnn::io::point_set: the points a file held, in the precision and dimension the file used,
// and visit_points(), which hands them to code templated on <T, D> (one branch per type).
// Not part of the public API: used by the frnn tool and the tests.
// Thread safety: a plain value type.
#pragma once
#include <cstddef>
#include <span>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "frnn/error.hpp"

namespace frnn::io {

enum class precision { f32, f64 };

inline std::string_view to_string(precision p) { return p == precision::f32 ? "float" : "double"; }

struct point_set {
    int dimension = 3;  ///< 2 or 3
    /// size() * dimension interleaved coordinates (x0 y0 [z0] x1 ...): float when the file
    /// stored float32, double otherwise.
    std::variant<std::vector<float>, std::vector<double>> coords{std::vector<double>{}};

    /// The precision of the coordinates.
    io::precision type() const { return coords.index() == 0 ? precision::f32 : precision::f64; }
    std::size_t size() const {
        return std::visit([&](const auto& v) { return v.size() / std::size_t(dimension); }, coords);
    }
    /// Converts the coordinates in place (float -> double is exact; double -> float rounds).
    void convert_to(io::precision p) {
        if (p == type()) return;
        std::visit(
            [&](const auto& v) {
                if (p == precision::f32)
                    coords = std::vector<float>(v.begin(), v.end());
                else
                    coords = std::vector<double>(v.begin(), v.end());
            },
            coords);
    }
};

/// Calls f.template operator()<T, D>(std::span<const T> coords) for the set's precision and
/// dimension, e.g. visit_points(p, [&]<class T, int D>(std::span<const T> xyz) { ... }).
template <class F>
decltype(auto) visit_points(const point_set& points, F&& f) {
    return std::visit(
        [&](const auto& v) -> decltype(auto) {
            using T = typename std::decay_t<decltype(v)>::value_type;
            const std::span<const T> xyz(v);
            if (points.dimension == 2) return f.template operator()<T, 2>(xyz);
            if (points.dimension != 3)
                throw error("point set has dimension " + std::to_string(points.dimension) +
                            ", expected 2 or 3");
            return f.template operator()<T, 3>(xyz);
        },
        points.coords);
}

}  // namespace frnn::io
