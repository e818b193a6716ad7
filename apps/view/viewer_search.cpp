// The search made visible in the window: the picked particle's searched cells and the cell grid
// block as lines in the scene, rings around the picked particle and its neighbors.
// gl.hpp first: it declares the OpenGL prototypes, which GLFW's own include of GL/gl.h omits.
#include "gl.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "line_renderer.hpp"
#include "picking.hpp"
#include "viewer.hpp"

namespace frnn::view {
namespace {
constexpr std::array<float, 3> grid_color{0.4f, 0.4f, 0.48f}, searched_color{0.3f, 0.85f, 1.0f};
}  // namespace

void viewer::refresh_search(const pointer_state& now) {
    std::optional<std::size_t> center = picked_;
    if (show_cell_grid_ && !ImGui::GetIO().WantCaptureMouse) {
        // O(N) per frame, only while the toggle is on.
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_, &w, &h);
        if (auto under = pick_particle(snapshot_, float(0.5 * snapshot_.spacing), cam_, scene_viewport(), h, now.x, now.y))
            center = under;
    }
    if (!show_cell_grid_) center.reset();
    if (!search_stale_ && center == grid_center_) return;
    search_stale_ = false;
    grid_center_ = center;
    search_ = picked_ ? search_of(snapshot_, *picked_) : particle_search{};
    grid_cells_.clear();
    if (center && *center < snapshot_.n)
        grid_cells_ = visited_cells(snapshot_, {snapshot_.x[*center * 3], snapshot_.x[*center * 3 + 1], snapshot_.x[*center * 3 + 2]});
    std::vector<line_vertex> lines = cell_lines(snapshot_, grid_cells_, grid_color);
    const auto searched = cell_lines(snapshot_, search_.cells, searched_color);
    lines.insert(lines.end(), searched.begin(), searched.end());  // drawn last: on top
    search_lines_->upload(lines);
}

void viewer::draw_pick_marker() {
    if (!picked_ || *picked_ >= snapshot_.n) return;
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const auto vp = scene_viewport();
    const mat4 projection = cam_.projection(float(vp[2]) / float(vp[3]));
    const mat4 m = multiply(projection, cam_.view());
    // A ring of `extra` pixels beyond particle k's drawn disc.
    const auto ring = [&](std::size_t k, float extra, ImU32 color, float thickness) {
        const float* p = &snapshot_.x[k * 3];
        float clip[4];
        for (int r = 0; r < 4; ++r)
            clip[r] = m[std::size_t(r)] * p[0] + m[std::size_t(4 + r)] * p[1] + m[std::size_t(8 + r)] * p[2] + m[std::size_t(12 + r)];
        if (clip[3] <= 0) return;  // behind the camera
        const float x = float(vp[0]) + (clip[0] / clip[3] + 1) / 2 * float(vp[2]);
        const float y = float(h) - (float(vp[1]) + (clip[1] / clip[3] + 1) / 2 * float(vp[3]));
        const float r = float(0.5 * snapshot_.spacing) * projection[5] * float(vp[3]) / 2 / clip[3];
        ImGui::GetForegroundDrawList()->AddCircle(ImVec2(x, y), r + extra, color, 24, thickness);
    };
    for (std::size_t j : search_.neighbors) ring(j, 1, IM_COL32(77, 217, 255, 255), 1.5f);
    ring(*picked_, 3, IM_COL32(255, 255, 255, 255), 2);
}

}  // namespace frnn::view
