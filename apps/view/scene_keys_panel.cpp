// The panel's Scene section and the one way a scene key changes. The section is generated from
// the scene's JSON as sim::scene_to_json writes it: every key gets a control by its JSON type,
// so a key the scene format gains appears here with no change. Both the controls and the
// `set_scene` script action go through viewer::set_scene_key, i.e. sim::with_scene_key: the
// scene parser checks every value.
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "frnn/sim/scene_keys.hpp"
#include "viewer.hpp"

namespace frnn::view {
namespace {
using json = nlohmann::json;

/// A control changed this frame: the key's path and its new value.
struct key_edit {
    std::string path;
    json value;
};

// Keys with controls of their own elsewhere in the panel.
bool has_other_control(const std::string& key) {
    return key == "solver" || key == "dim" || key == "particles"  // scene, solver, 2D/3D, particles
           || key == "gravity"                                    // changes live
           || key == "viscoelastic" || key == "sph";              // the parameter table
}

/// Drag speed: a hundredth of the value's size per pixel.
float drag_speed(double size) { return float(0.01 * std::max(size, 0.1)); }

bool is_vector(const json& v) {
    return v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); });
}

void draw_leaf(const std::string& label, const std::string& path, const json& v, std::optional<key_edit>& edit) {
    ImGui::PushID(path.c_str());
    if (v.is_boolean()) {
        bool on = v.get<bool>();
        if (ImGui::Checkbox(label.c_str(), &on)) edit = key_edit{path, on};
    } else if (v.is_number_integer()) {
        auto n = v.get<std::int64_t>();
        const std::int64_t one = 1;
        if (ImGui::InputScalar(label.c_str(), ImGuiDataType_S64, &n, &one)) edit = key_edit{path, n};
    } else if (v.is_number()) {
        double x = v.get<double>();
        if (ImGui::DragScalar(label.c_str(), ImGuiDataType_Double, &x, drag_speed(std::abs(x)), nullptr, nullptr, "%.6g"))
            edit = key_edit{path, x};
    } else if (is_vector(v)) {
        std::vector<double> xs = v.get<std::vector<double>>();
        double size = 0;
        for (double x : xs) size = std::max(size, std::abs(x));
        if (ImGui::DragScalarN(label.c_str(), ImGuiDataType_Double, xs.data(), int(xs.size()), drag_speed(size), nullptr,
                               nullptr, "%.4g"))
            edit = key_edit{path, xs};
    } else if (v.is_string()) {
        const std::string now = v.get<std::string>();
        const auto choices = sim::scene_key_choices(path);
        if (!choices.empty()) {
            if (ImGui::BeginCombo(label.c_str(), now.c_str())) {
                for (const auto& c : choices)
                    if (ImGui::Selectable(c.c_str(), c == now)) edit = key_edit{path, c};
                ImGui::EndCombo();
            }
        } else {
            char text[1024];
            std::snprintf(text, sizeof text, "%s", now.c_str());
            if (ImGui::InputText(label.c_str(), text, sizeof text)) edit = key_edit{path, std::string(text)};
        }
    } else {
        ImGui::TextDisabled("%s: %s", label.c_str(), v.dump().c_str());  // not written by the scene writer today
    }
    ImGui::PopID();
}

/// The keys of an object (or the elements of an array of objects) under `path`.
void draw_keys(const json& j, const std::string& path, std::optional<key_edit>& edit) {
    if (j.is_array()) {
        for (std::size_t i = 0; i < j.size(); ++i) {
            const std::string at = path + "[" + std::to_string(i) + "]";
            const json& e = j[i];
            const std::string label = at + (e.contains("name") ? " " + e["name"].get<std::string>() : "") +
                                      (e.contains("type") ? " (" + e["type"].get<std::string>() + ")" : "");
            if (ImGui::TreeNode(at.c_str(), "%s", label.c_str())) {
                draw_keys(e, at, edit);
                ImGui::TreePop();
            }
        }
        return;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string at = path.empty() ? it.key() : path + "." + it.key();
        if ((it->is_object() || (it->is_array() && !is_vector(*it)))) {
            if (ImGui::TreeNode(at.c_str(), "%s", it.key().c_str())) {
                draw_keys(*it, at, edit);
                ImGui::TreePop();
            }
        } else {
            draw_leaf(it.key(), at, *it, edit);
        }
    }
}

}  // namespace

void viewer::set_scene_key(const std::string& path, const std::string& value_json) {
    sim::scene next = sim::with_scene_key(scene_, path, value_json, "scene '" + scene_.name + "'");
    for (const auto& p : sim::parameters())
        if (p.get(next) != p.get(scene_)) runner_->set_parameter(p, p.get(next));
    if (next.gravity != scene_.gravity) runner_->set_gravity(next.gravity);
    sim::scene waiting = next;  // what remains once the live changes are taken away
    waiting.viscoelastic = scene_.viscoelastic, waiting.sph = scene_.sph, waiting.gravity = scene_.gravity;
    if (sim::scene_to_json(waiting) != sim::scene_to_json(scene_)) reset_pending_ = true;
    scene_ = std::move(next);
    show_scene_choices();
    scene_changed_ = true;  // the outline shows the edited scene
}

void viewer::draw_scene_keys() {
    if (!ImGui::CollapsingHeader("Scene keys")) return;
    if (reset_pending_) ImGui::TextColored(ImVec4(1, 0.8f, 0.3f, 1), "edited: Reset runs the scene as shown");
    else ImGui::TextDisabled("changes apply on Reset (the outline shows them now)");
    const json j = json::parse(sim::scene_to_json(scene_));
    json shown = json::object();
    for (auto it = j.begin(); it != j.end(); ++it)
        if (!has_other_control(it.key())) shown[it.key()] = *it;
    std::optional<key_edit> edit;
    ImGui::PushItemWidth(-140);  // room for the labels, however deep the tree
    draw_keys(shown, "", edit);
    ImGui::PopItemWidth();
    if (!edit) return;
    try {
        set_scene_key(edit->path, edit->value.dump());
    } catch (const std::exception& e) {
        message_ = e.what();
    }
}

}  // namespace frnn::view
