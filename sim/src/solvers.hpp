// The solvers' makers, one per solver file; make_solver (solver_factory.cpp) picks one.
#pragma once
#include <memory>

#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

namespace frnn::sim::detail {

std::unique_ptr<solver> make_viscoelastic(const scene& s, int threads);  // viscoelastic.cpp
std::unique_ptr<solver> make_sph(const scene& s, int threads);           // sph.cpp

}  // namespace frnn::sim::detail
