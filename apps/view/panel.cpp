// The control panel (Dear ImGui) and the color legend. The parameter section is generated from
// frnn::sim's parameter table: a row added there gets its control here with no change.
// gl.hpp first: it declares the OpenGL prototypes, which GLFW's own include of GL/gl.h omits.
#include "gl.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cmath>
#include <cstdio>

#include "colormap.hpp"
#include "viewer.hpp"

namespace frnn::view {
namespace {

ImU32 packed(const std::array<float, 3>& c) {
    return IM_COL32(int(std::lround(c[0] * 255)), int(std::lround(c[1] * 255)), int(std::lround(c[2] * 255)), 255);
}

}  // namespace

void viewer::draw_legend() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const float x0 = 20, y1 = float(h) - 30, x1 = x0 + 300, y0 = y1 - 18;
    legend_rect_ = {x0, y0, x1, y1};
    ImDrawList* d = ImGui::GetForegroundDrawList();
    // One gradient per piece of the map: the rasterizer interpolates linearly, as the map does.
    const std::size_t pieces = colormap_stops.size() - 1;
    for (std::size_t k = 0; k < pieces; ++k) {
        const float a = x0 + (x1 - x0) * float(k) / float(pieces), b = x0 + (x1 - x0) * float(k + 1) / float(pieces);
        const ImU32 left = packed(colormap_stops[k]), right = packed(colormap_stops[k + 1]);
        d->AddRectFilledMultiColor(ImVec2(a, y0), ImVec2(b, y1), left, right, right, left);
    }
    char text[128];
    std::snprintf(text, sizeof text, "%.4g", double(shown_min_));
    d->AddText(ImVec2(x0, y0 - 16), IM_COL32(230, 230, 230, 255), text);
    std::snprintf(text, sizeof text, "%.4g", double(shown_max_));
    d->AddText(ImVec2(x1 - ImGui::CalcTextSize(text).x, y0 - 16), IM_COL32(230, 230, 230, 255), text);
    const char* name = field_names[std::size_t(field_)];
    d->AddText(ImVec2(0.5f * (x0 + x1) - 0.5f * ImGui::CalcTextSize(name).x, y0 - 16), IM_COL32(230, 230, 230, 255), name);
}

void viewer::draw_parameters() {
    const std::string active = sim::parameter_section(scene_.solver);
    for (const char* section : {"viscoelastic", "sph"}) {
        const bool mine = active == section;
        ImGui::SetNextItemOpen(mine, ImGuiCond_Always);
        if (!ImGui::CollapsingHeader(mine ? (std::string(section) + " (running)").c_str() : section)) continue;
        for (const auto& p : sim::parameters()) {
            if (p.section != section) continue;
            ImGui::PushID(p.name().c_str());
            const double before = p.get(scene_);
            double value = before;
            const std::string label = p.key + (p.unit == "1" ? "" : " [" + p.unit + "]") + (p.live ? "" : " *");
            switch (p.kind) {
            case sim::parameter_kind::real: {
                const double lo = p.ui_min, hi = p.ui_max;
                ImGui::SliderScalar(label.c_str(), ImGuiDataType_Double, &value, &lo, &hi, "%.4g",
                                    ImGuiSliderFlags_AlwaysClamp | (p.log_scale ? ImGuiSliderFlags_Logarithmic : 0));
                break;
            }
            case sim::parameter_kind::boolean: {
                bool on = value != 0;
                ImGui::Checkbox(label.c_str(), &on);
                value = on ? 1 : 0;
                break;
            }
            case sim::parameter_kind::choice: {
                int index = int(value);
                std::vector<const char*> names;
                for (const auto& c : p.choices) names.push_back(c.c_str());
                ImGui::Combo(label.c_str(), &index, names.data(), int(names.size()));
                value = index;
                break;
            }
            }
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("%s%s", p.help.c_str(), p.live ? "" : " (* restarts the scene)");
            // A slider reports every drag movement; a restarting parameter waits for the release.
            const bool commit = p.live || p.kind != sim::parameter_kind::real || ImGui::IsItemDeactivatedAfterEdit();
            if (value != before) p.set(scene_, value);
            if (commit && (value != before || ImGui::IsItemDeactivatedAfterEdit())) runner_->set_parameter(p, p.get(scene_));
            ImGui::PopID();
        }
    }
}

bool viewer::panel_button(const char* label) {
    const bool pressed = ImGui::Button(label);
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    buttons_[label] = {a.x, a.y, b.x, b.y};  // where the `button` script action clicks
    return pressed;
}

void viewer::draw_panel() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    ImGui::SetNextWindowPos(ImVec2(float(w) - panel_width, 0), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(panel_width, float(h)), ImGuiCond_Always);
    ImGui::Begin("frnn view", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    const auto button = [&](const char* label) { return panel_button(label); };

    ImGui::Text("%s: %s %dD, %zu particles", scene_.name.c_str(), sim::to_string(scene_.solver).c_str(), scene_.dim, snapshot_.n);
    ImGui::Text("step %llu, t = %.4f s, %.0f fps", (unsigned long long)snapshot_.step, snapshot_.time, double(ImGui::GetIO().Framerate));
    ImGui::Text("step %.2f ms, copy %.2f ms", runner_->mean_step_ms(), runner_->mean_copy_ms());
    if (picked_ && *picked_ < snapshot_.n) {
        const std::size_t k = *picked_;
        ImGui::Text("particle %zu at (%.4g, %.4g, %.4g)", k, double(snapshot_.x[k * 3]), double(snapshot_.x[k * 3 + 1]),
                    double(snapshot_.x[k * 3 + 2]));
        ImGui::Text("speed %.4g, density %.4g, pressure %.4g", double(snapshot_.speed[k]), double(snapshot_.density[k]),
                    double(snapshot_.pressure[k]));
        ImGui::Text("%u neighbors in the last step's lists", snapshot_.neighbors[k]);
        if (snapshot_.geometry.slots > 0)
            ImGui::Text("%zu within r = %.4g now, in %zu cells", search_.neighbors.size(), snapshot_.radius, search_.cells.size());
    } else {
        ImGui::TextDisabled("click a particle to see its fields");
    }
    const std::string err = runner_->last_error();
    if (!err.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", err.c_str());

    if (button(playing_ ? "Pause" : "Play")) toggle_play();
    ImGui::SameLine();
    if (button("Step")) step();
    ImGui::SameLine();
    if (button("Reset")) reset();
    ImGui::SameLine();
    if (button("Reset view")) cam_.reset();
    if (ImGui::Checkbox("cell grid (g)", &show_cell_grid_)) search_stale_ = true;
    if (ImGui::SliderFloat("time scale", &time_scale_, 0, 4, time_scale_ == 0 ? "as fast as possible" : "%.2f"))
        runner_->set_time_scale(time_scale_);

    ImGui::Separator();
    int f = int(field_);
    if (ImGui::Combo("color by", &f, field_names.data(), int(field_names.size()))) field_ = field(f), scene_changed_ = true;
    ImGui::Checkbox("automatic range", &auto_range_);
    if (!auto_range_) {
        ImGui::InputFloat("min", &range_min_, 0, 0, "%.4g");
        ImGui::InputFloat("max", &range_max_, 0, 0, "%.4g");
    }

    ImGui::Separator();
    const auto names = sim::builtin_scene_names();
    std::vector<const char*> scene_items;
    for (const auto& n : names) scene_items.push_back(n.c_str());
    if (!opt_.scene_file.empty()) scene_items.push_back(opt_.scene_file.c_str());
    ImGui::Combo("scene", &chosen_scene_, scene_items.data(), int(scene_items.size()));
    const char* solvers[] = {"viscoelastic", "sph"};
    ImGui::Combo("solver", &chosen_solver_, solvers, 2);
    ImGui::RadioButton("2D", &chosen_dim_, 2);
    ImGui::SameLine();
    ImGui::RadioButton("3D", &chosen_dim_, 3);
    ImGui::InputInt("particles", &chosen_particles_, 0, 0);
    chosen_particles_ = std::clamp(chosen_particles_, 1, 1 << 22);
    if (button("Apply scene")) {
        try {
            const std::string chosen = std::size_t(chosen_scene_) < names.size() ? names[std::size_t(chosen_scene_)] : opt_.scene_file;
            sim::scene next = std::size_t(chosen_scene_) < names.size() ? sim::builtin_scene(chosen) : sim::load_scene(chosen);
            // The same scene keeps the solver parameters edited in the panel (its geometry is
            // read again: a 2D scene's colliders are flattened and cannot go back to 3D).
            if (chosen == scene_label_) next.viscoelastic = scene_.viscoelastic, next.sph = scene_.sph;
            sim::scene_overrides o;
            o.solver = chosen_solver_ == 1 ? sim::solver_kind::sph : sim::solver_kind::viscoelastic;
            o.dim = chosen_dim_;
            o.particles = std::size_t(chosen_particles_);
            sim::apply(next, o);
            switch_scene(std::move(next));
            scene_label_ = chosen;
            message_.clear();
        } catch (const std::exception& e) {
            message_ = e.what();
        }
    }
    if (ImGui::DragFloat3("gravity [m/s^2]", gravity_.data(), 0.05f, -50, 50, "%.2f")) {
        const sim::vec3 g{gravity_[0], gravity_[1], gravity_[2]};
        scene_.gravity = g;
        runner_->set_gravity(g);
    }

    ImGui::Separator();
    char path[512];
    std::snprintf(path, sizeof path, "%s", save_path_.c_str());
    if (ImGui::InputText("file", path, sizeof path)) save_path_ = path;
    if (button("Save scene")) save_scene(save_path_);
    std::snprintf(path, sizeof path, "%s", state_path_.c_str());
    if (ImGui::InputText("checkpoint", path, sizeof path)) state_path_ = path;
    if (button("Save state")) save_state(state_path_);
    ImGui::SameLine();
    if (button("Load state")) load_state(state_path_);
    std::snprintf(path, sizeof path, "%s", record_dir_.c_str());
    if (ImGui::InputText("recording", path, sizeof path)) record_dir_ = path;
    if (recorder_.recording()) {
        if (button("Stop recording")) stop_recording();
        ImGui::SameLine();
        ImGui::Text("%zu frames", recorder_.frames());
    } else if (button("Record")) {
        start_recording(record_dir_);
    }
    if (!message_.empty()) ImGui::TextWrapped("%s", message_.c_str());

    ImGui::Separator();
    draw_colliders();

    ImGui::Separator();
    draw_profile();

    ImGui::Separator();
    draw_scene_keys();

    ImGui::Separator();
    ImGui::TextDisabled("parameters (* restarts the scene)");
    draw_parameters();
    ImGui::End();
}

}  // namespace frnn::view
