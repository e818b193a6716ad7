// A shipped scene made small for tests: its solver, dimension and particle count overridden.
#pragma once
#include <string>

#include "frnn/sim/scene.hpp"

namespace frnn::test {

inline sim::scene small_scene(const std::string& name, sim::solver_kind solver, int dim, std::size_t particles) {
    sim::scene s = sim::builtin_scene(name);
    sim::scene_overrides o;
    o.solver = solver;
    o.dim = dim;
    o.particles = particles;
    sim::apply(s, o);
    return s;
}

}  // namespace frnn::test
