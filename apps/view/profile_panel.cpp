// The panel's Profile section: where a step's time goes, live. One bar, a segment per solver
// stage (the simulation thread's recent times) and one for drawing the frame, so the stage that
// dominates is seen at a glance; "Capture profile" writes a Chrome trace of the next steps.
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <string>
#include <vector>

#include "viewer.hpp"

namespace frnn::view {
namespace {

// One color per sim::stage (and a last one for drawing), told apart at a glance.
constexpr ImU32 segment_colors[] = {
    IM_COL32(31, 119, 180, 255), IM_COL32(255, 127, 14, 255), IM_COL32(44, 160, 44, 255),  IM_COL32(214, 39, 40, 255),
    IM_COL32(148, 103, 189, 255), IM_COL32(140, 86, 75, 255), IM_COL32(227, 119, 194, 255), IM_COL32(188, 189, 34, 255),
    IM_COL32(23, 190, 207, 255),  IM_COL32(255, 187, 120, 255), IM_COL32(127, 127, 127, 255),
    IM_COL32(240, 240, 240, 255)};
static_assert(std::size(segment_colors) >= std::size_t(sim::stage::count) + 1);

struct segment {
    std::string name;
    double ms;
    ImU32 color;
};

}  // namespace

void viewer::draw_profile() {
    if (!ImGui::CollapsingHeader("profile", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Text("%.1f steps/s, %.1f frames/s", steps_per_second_, double(ImGui::GetIO().Framerate));
    const auto stage_ms = runner_->recent_stage_ms();
    std::vector<segment> segments;
    for (std::size_t k = 0; k < stage_ms.size(); ++k)
        if (stage_ms[k] > 0) segments.push_back({sim::to_string(sim::stage(k)), stage_ms[k], segment_colors[k]});
    segments.push_back({"drawing", draw_ms_, segment_colors[std::size_t(sim::stage::count)]});
    double total = 0;
    for (const auto& s : segments) total += s.ms;

    // The bar: segment widths proportional to milliseconds; hovering one names it.
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x, height = 16;
    ImDrawList* d = ImGui::GetWindowDrawList();
    float x = at.x;
    for (std::size_t k = 0; k < segments.size() && total > 0; ++k) {
        const float w = width * float(segments[k].ms / total);
        d->AddRectFilled(ImVec2(x, at.y), ImVec2(x + w, at.y + height), segments[k].color);
        if (ImGui::IsMouseHoveringRect(ImVec2(x, at.y), ImVec2(x + w, at.y + height)))
            ImGui::SetTooltip("%s: %.2f ms", segments[k].name.c_str(), segments[k].ms);
        x += w;
    }
    ImGui::Dummy(ImVec2(width, height));
    for (const segment& s : segments) {
        ImGui::ColorButton(s.name.c_str(), ImGui::ColorConvertU32ToFloat4(s.color),
                           ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoBorder, ImVec2(10, 10));
        ImGui::SameLine();
        ImGui::Text("%-22s %7.2f ms", s.name.c_str(), s.ms);
    }

    ImGui::InputInt("steps##profile", &profile_steps_, 0, 0);
    profile_steps_ = std::clamp(profile_steps_, 1, 100000);
    char path[512];
    std::snprintf(path, sizeof path, "%s", profile_path_.c_str());
    if (ImGui::InputText("trace", path, sizeof path)) profile_path_ = path;
    if (panel_button("Capture profile")) capture_profile(profile_steps_, profile_path_);
    const std::string status = runner_->capture_status();
    if (!status.empty()) ImGui::TextWrapped("%s", status.c_str());
}

}  // namespace frnn::view
