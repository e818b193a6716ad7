// `--state FILE`: the end of a run as JSON, for tests: the step and time, the particles in id
// order with every field, the colliders posed at that time (as the simulation has them: place,
// orientation, velocity) and the selected one, the camera, the legend's pixels and range, the
// picked particle's search (its cells and neighbors, and the grid they come
// from), the recent time of each stage and how many frames were drawn during a single step.
// gl.hpp first: it declares the OpenGL prototypes, which GLFW's own include of GL/gl.h omits.
#include "gl.hpp"

#include <GLFW/glfw3.h>

#include <nlohmann/json.hpp>

#include "frnn/io/atomic_file.hpp"
#include "frnn/sim/output.hpp"
#include "viewer.hpp"

namespace frnn::view {

void viewer::write_state(const std::string& path) const {
    using json = nlohmann::json;
    const sim::scene s = runner_->scene_copy();
    json j;
    j["scene"] = s.name;
    j["solver"] = sim::to_string(s.solver);
    j["dim"] = snapshot_.dim;
    j["step"] = snapshot_.step;
    j["time"] = snapshot_.time;
    j["spacing"] = snapshot_.spacing;
    j["particles"] = snapshot_.n;
    j["x"] = snapshot_.x;
    j["speed"] = snapshot_.speed;
    j["density"] = snapshot_.density;
    j["pressure"] = snapshot_.pressure;
    j["neighbors"] = snapshot_.neighbors;
    j["colliders"] = json::array();
    const sim::collider_set set(s.colliders);
    for (const auto& p : set.at(snapshot_.time)) {
        const sim::collider& c = p.desc();
        json cj;
        cj["name"] = c.name;
        cj["type"] = c.kind == sim::shape::plane ? "plane" : c.kind == sim::shape::sphere ? "sphere" : "box";
        const sim::vec3 center = p.to_world({0, 0, 0});
        cj["center"] = {center[0], center[1], center[2]};
        if (c.kind == sim::shape::sphere) cj["radius"] = c.radius;
        if (c.kind == sim::shape::box) cj["half"] = {c.half[0], c.half[1], c.half[2]};
        if (c.kind == sim::shape::plane) {
            sim::vec3 n{};
            p.phi(center, n);
            cj["normal"] = {n[0], n[1], n[2]};
        }
        // Its orientation (rows of the local-to-world rotation) and the velocity of its center.
        json rows = json::array({json::array(), json::array(), json::array()});
        for (int a = 0; a < 3; ++a) {
            sim::vec3 unit{0, 0, 0};
            unit[a] = 1;
            const sim::vec3 column = p.to_world(unit);
            for (int r = 0; r < 3; ++r) rows[std::size_t(r)].push_back(column[r] - center[r]);
        }
        cj["rotation"] = rows;
        const sim::vec3 v = p.velocity_at(center);
        cj["velocity"] = {v[0], v[1], v[2]};
        j["colliders"].push_back(cj);
    }
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const vec3f eye = cam_.eye(), target = cam_.target(), up = cam_.up();
    j["camera"] = {{"plane_view", cam_.plane_view()}, {"eye", eye},         {"target", target},
                   {"up", up},                         {"fov", cam_.fov_degrees()}, {"half_height", cam_.half_height()},
                   {"width", w},                       {"height", h},
                   {"viewport", scene_viewport()}};  // x, y (from the bottom), width, height
    j["legend"] = {{"field", field_names[std::size_t(field_)]},
                   {"min", shown_min_},
                   {"max", shown_max_},
                   {"rect", legend_rect_}};
    j["picked"] = picked_ ? json(*picked_) : json(nullptr);
    j["selected_collider"] = selected_collider_ ? json(*selected_collider_) : json(nullptr);
    // The search made visible, with the grid it comes from so tests can recompute it.
    const auto& g = snapshot_.geometry;
    j["search"] = {{"radius", snapshot_.radius},
                   {"grid", {{"origin", g.origin}, {"cell", g.cell}, {"dims", g.dims}, {"scale", g.scale}, {"reach", g.reach},
                             {"periodic", g.periodic}}},
                   {"neighbors", search_.neighbors},
                   {"cells", search_.cells},
                   {"cell_grid", show_cell_grid_},
                   {"grid_cells", grid_cells_}};
    json stages = json::object();
    const auto stage_ms = runner_->recent_stage_ms();
    for (std::size_t k = 0; k < stage_ms.size(); ++k) stages[sim::to_string(sim::stage(k))] = stage_ms[k];
    j["profile"] = {{"stage_ms", stages},
                    {"drawing_ms", draw_ms_},
                    {"steps_per_second", steps_per_second_},
                    {"capture", runner_->capture_status()}};
    j["frames"] = frame_;
    j["max_frames_in_one_step"] = max_frames_in_step_;
    j["playing"] = playing_;
    j["error"] = runner_->last_error();
    io::write_file_atomically(path, j.dump() + "\n");
}

}  // namespace frnn::view
