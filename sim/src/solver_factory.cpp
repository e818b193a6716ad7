// make_solver: the scene's solver, by its kind and dimension.
#include <algorithm>
#include <limits>
#include <memory>
#include <string>

#include "frnn/error.hpp"
#include "frnn/sim/solver.hpp"
#include "solvers.hpp"

namespace frnn::sim {

void solver::set_ranks(std::shared_ptr<rank_comm>, const balance_options&) {
    throw ranks_agree_error("the " + to_string(get_scene().solver) +
                            " solver runs in one process only (across ranks: --solver sph)");
}

double solver::largest_coordinate(int axis) {
    const particle_view p = view();
    double m = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p.n; ++i) m = std::max(m, double(p.x[i * std::size_t(p.dim) + std::size_t(axis)]));
    return m;
}

std::unique_ptr<solver> make_solver(const scene& s, int threads) {
    if (s.dim != 2 && s.dim != 3) throw error("scene '" + s.name + "': dim must be 2 or 3, got " + std::to_string(s.dim));
    return s.solver == solver_kind::sph ? detail::make_sph(s, threads) : detail::make_viscoelastic(s, threads);
}

}  // namespace frnn::sim
