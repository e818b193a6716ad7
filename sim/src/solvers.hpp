// The solvers' makers, one per solver file; make_solver (solver_factory.cpp) picks one.
#pragma once
#include <memory>
#include <string_view>

#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

namespace frnn::sim::detail {

std::unique_ptr<solver> make_viscoelastic(const scene& s, int threads);  // viscoelastic.cpp
/// level: the pair kernels' instruction-set level (sph_pairs.hpp); empty: the widest available.
std::unique_ptr<solver> make_sph(const scene& s, int threads, std::string_view level = {});  // sph.cpp

}  // namespace frnn::sim::detail
