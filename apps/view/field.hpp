// The per-particle fields the viewer colors by, read from a snapshot.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "frnn/sim/simulation.hpp"

namespace frnn::view {

enum class field { speed, density, pressure, neighbors, id };
inline constexpr std::array<const char*, 5> field_names = {"speed", "density", "pressure", "neighbors", "id"};

/// The field's value of every particle, in the snapshot's (id) order.
inline void field_values(const sim::particle_snapshot& s, field f, std::vector<float>& out) {
    out.resize(s.n);
    for (std::size_t k = 0; k < s.n; ++k) {
        switch (f) {
        case field::speed: out[k] = s.speed[k]; break;
        case field::density: out[k] = s.density[k]; break;
        case field::pressure: out[k] = s.pressure[k]; break;
        case field::neighbors: out[k] = float(s.neighbors[k]); break;
        case field::id: out[k] = float(k); break;
        }
    }
}

/// The field named `name`; false if there is none.
inline bool field_by_name(const std::string& name, field& out) {
    for (std::size_t i = 0; i < field_names.size(); ++i)
        if (name == field_names[i]) {
            out = field(i);
            return true;
        }
    return false;
}

}  // namespace frnn::view
