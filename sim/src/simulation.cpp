// A scene stepped one step at a time; snapshots in particle-id order.
#include "frnn/sim/simulation.hpp"

#include <cmath>
#include <fstream>

#include "checkpoint.hpp"
#include "frnn/error.hpp"

namespace frnn::sim {

simulation::simulation(scene s, int threads) : scene_(std::move(s)), threads_(threads), solver_(make_solver(scene_, threads)) {}

void simulation::step() { solver_->step(prof_); }

void simulation::reset() {
    solver_ = make_solver(scene_, threads_);
    prof_ = profiler();
}

void simulation::set_scene(scene s) {
    auto fresh = make_solver(s, threads_);  // a scene that fails to seed leaves this one running
    scene_ = std::move(s);
    solver_ = std::move(fresh);
    prof_ = profiler();
}

bool simulation::set_parameter(const parameter& p, double value) {
    check_parameter_value(p, value);
    scene next = scene_;
    p.set(next, value);
    if (p.section != parameter_section(scene_.solver)) {
        scene_ = std::move(next);  // kept for when the solver is switched
        return false;
    }
    if (p.live) {
        solver_->set_parameters(next);
        scene_ = std::move(next);
        return false;
    }
    set_scene(std::move(next));
    return true;
}

void simulation::set_gravity(const vec3& g) {
    scene next = scene_;
    next.gravity = g;
    solver_->set_parameters(next);
    scene_ = std::move(next);
}

void simulation::set_colliders(std::vector<collider> colliders) {
    if (scene_.dim == 2)
        for (auto& c : colliders) flatten_to_2d(c);
    solver_->set_colliders(colliders);
    scene_.colliders = std::move(colliders);
}

void simulation::save_checkpoint(const std::string& path) const {
    detail::checkpoint_header h;
    h.scene_json = scene_to_json(scene_);
    h.origin = "checkpoint " + path;
    // No frames written yet: a run resumed from here writes its first frame after one step.
    detail::write_checkpoint(path, h, *solver_);
}

void simulation::load_checkpoint(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw error("cannot open checkpoint '" + path + "'");
    const detail::checkpoint_header h = detail::read_checkpoint_header(in, "'" + path + "'");
    scene s = parse_scene(h.scene_json, h.origin);
    apply(s, h.ov);
    auto fresh = make_solver(s, threads_);
    fresh->load(in);
    scene_ = std::move(s);
    solver_ = std::move(fresh);
    prof_ = profiler();
}

void simulation::snapshot(particle_snapshot& out) const {
    const particle_view v = solver_->view();
    const int d = v.dim;
    out.dim = d;
    out.step = solver_->steps();
    out.time = solver_->time();
    out.spacing = solver_->spacing();
    out.radius = solver_->radius();
    out.geometry = solver_->geometry();
    out.n = v.n;
    out.x.assign(v.n * 3, 0.f);
    out.speed.resize(v.n);
    out.density.resize(v.n);
    out.pressure.resize(v.n);
    out.neighbors.resize(v.n);
    for (std::size_t i = 0; i < v.n; ++i) {
        const std::size_t k = v.id[i];  // the solver keeps cell order; the snapshot id order
        double s2 = 0;
        for (int a = 0; a < d; ++a) {
            out.x[k * 3 + std::size_t(a)] = v.x[i * std::size_t(d) + std::size_t(a)];
            const double c = v.v[i * std::size_t(d) + std::size_t(a)];
            s2 += c * c;
        }
        out.speed[k] = float(std::sqrt(s2));
        out.density[k] = v.rho[i];
        out.pressure[k] = v.p[i];
        out.neighbors[k] = solver_->neighbor_count(i);
    }
}

}  // namespace frnn::sim
