// Colliders by hand in the window: a left press on a collider selects and grabs it, the drag
// moves it (in the view plane through its center; with Shift along the view direction), `[`
// and `]` turn it, the panel adds spheres and boxes and deletes the selected one. Every edit
// changes the scene as edited (what Save scene writes and Reset runs) and reaches the running
// simulation at once; while held, the collider pushes the fluid with the hand's velocity
// (collider_hand.hpp).
// gl.hpp first: it declares the OpenGL prototypes, which GLFW's own include of GL/gl.h omits.
#include "gl.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cstdio>

#include "collider_editing.hpp"
#include "viewer.hpp"

namespace frnn::view {
namespace {
constexpr double radians_per_degree = 3.14159265358979323846 / 180;
}  // namespace

bool viewer::grab_collider(const pointer_state& now) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const auto hit = pick_collider(scene_, snapshot_.time, pixel_ray(cam_, scene_viewport(), h, now.x, now.y));
    if (!hit) return false;
    selected_collider_ = hit;
    scene_changed_ = true;  // the outline
    return true;
}

void viewer::drag_collider(const pointer_state& now) {
    if (!selected_collider_ || *selected_collider_ >= scene_.colliders.size()) return;
    sim::collider& c = scene_.colliders[*selected_collider_];
    const sim::vec3 center = sim::posed_collider(c, snapshot_.time).to_world({0, 0, 0});
    const vec3f forward = normalize(cam_.target() - cam_.eye());
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const auto vp = scene_viewport();
    const pointer_ray ray = pixel_ray(cam_, vp, h, now.x, now.y), before = pixel_ray(cam_, vp, h, last_pointer_.x, last_pointer_.y);
    sim::vec3 move{0, 0, 0};
    if (now.shift) {
        if (scene_.dim == 3) {  // up the screen is away from the eye, at the pixels' size there
            const vec3f eye = cam_.eye();
            const float depth = dot(vec3f{float(center[0]), float(center[1]), float(center[2])} - eye, forward);
            const float along = float(last_pointer_.y - now.y) * ray.pixel_at(depth);
            for (int a = 0; a < 3; ++a) move[a] = along * forward[a];
        }
    } else {
        // The points under the pointer now and at the last frame, on the plane through the
        // center facing the eye: the collider keeps its place under the pointer.
        const auto to = on_plane(ray, center, forward), from = on_plane(before, center, forward);
        if (to && from)
            for (int a = 0; a < 3; ++a) move[a] = (*to)[a] - (*from)[a];
    }
    if (scene_.dim == 2) move[2] = 0;
    for (int a = 0; a < 3; ++a) c.center[a] += move[a];
    scene_changed_ = true;
    send_colliders(true);  // every frame, also unmoved: a resting hand stops the collider
}

void viewer::release_collider() {
    holding_collider_ = false;
    send_colliders(false);
}

void viewer::send_colliders(bool held) {
    runner_->set_colliders(scene_.colliders, held ? selected_collider_ : std::nullopt);
}

void viewer::add_collider(sim::shape kind) {
    const vec3f t = cam_.target();
    scene_.colliders.push_back(new_collider(kind, scene_, {t[0], t[1], t[2]}, snapshot_.x, snapshot_.spacing));
    selected_collider_ = scene_.colliders.size() - 1;
    holding_collider_ = false;
    scene_changed_ = true;
    send_colliders(false);
}

void viewer::delete_collider() {
    if (!selected_collider_ || *selected_collider_ >= scene_.colliders.size()) return;
    scene_.colliders.erase(scene_.colliders.begin() + std::ptrdiff_t(*selected_collider_));
    selected_collider_.reset();
    holding_collider_ = false;
    scene_changed_ = true;
    send_colliders(false);
}

void viewer::rotate_collider(double degrees) {
    if (!selected_collider_ || *selected_collider_ >= scene_.colliders.size()) return;
    // About the direction toward the eye: counterclockwise on the screen for degrees > 0.
    const vec3f back = normalize(cam_.eye() - cam_.target());
    sim::collider& c = scene_.colliders[*selected_collider_];
    c = turned(c, {back[0], back[1], back[2]}, degrees * radians_per_degree);
    if (scene_.dim == 2) sim::flatten_to_2d(c);
    scene_changed_ = true;
    send_colliders(holding_collider_);
}

void viewer::draw_colliders() {
    ImGui::TextDisabled("colliders: click selects, drag moves,");
    ImGui::TextDisabled("Shift+drag: along the view, [ ]: rotate");
    for (std::size_t k = 0; k < scene_.colliders.size(); ++k) {
        const sim::collider& c = scene_.colliders[k];
        char label[160];
        std::snprintf(label, sizeof label, "%zu: %s (%s%s)", k, c.name.c_str(), sim::collider_types()[std::size_t(c.kind)].c_str(),
                      c.inside ? ", container" : "");
        if (ImGui::Selectable(label, selected_collider_ == k)) selected_collider_ = k, scene_changed_ = true;
    }
    if (panel_button("Add sphere")) add_collider(sim::shape::sphere);
    ImGui::SameLine();
    if (panel_button("Add box")) add_collider(sim::shape::box);
    if (!selected_collider_) return;
    ImGui::SameLine();
    if (panel_button("Delete")) delete_collider();
    if (panel_button("Rotate +15")) rotate_collider(rotate_step_degrees);
    ImGui::SameLine();
    if (panel_button("Rotate -15")) rotate_collider(-rotate_step_degrees);
}

}  // namespace frnn::view
