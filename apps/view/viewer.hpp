// The viewer window: GLFW + OpenGL 3.3 core + Dear ImGui. Each frame it takes the newest
// snapshot from the simulation thread (one upload), draws the scene outline and the particles,
// the legend and the control panel; under a script it applies the frame's actions first and
// runs its S steps in lockstep.
#pragma once
#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera.hpp"
#include "field.hpp"
#include "options.hpp"
#include "recorder.hpp"
#include "script.hpp"
#include "search_view.hpp"
#include "sim_runner.hpp"

struct GLFWwindow;

namespace frnn::view {

class particle_renderer;
class line_renderer;

/// A pointer as scripts drive it (pixels from the window's top-left).
struct pointer_state {
    double x = 0, y = 0;
    std::array<bool, 3> down{false, false, false};
    bool shift = false;  ///< a drag with Shift moves a collider along the view direction
};

/// Width of the control panel at the window's right edge, in pixels.
inline constexpr float panel_width = 380;

class viewer {
public:
    /// Opens the window (throws frnn::error when there is no display or no OpenGL 3.3).
    viewer(const sim::scene& s, const view_options& o);
    ~viewer();
    viewer(const viewer&) = delete;
    viewer& operator=(const viewer&) = delete;
    /// Runs until the window closes or the frame limit; returns the exit code.
    int run();

    // Input, called from GLFW callbacks.
    void on_key(int key);
    void on_scroll(double steps);

private:
    void frame();
    void apply_actions();
    void apply(const script_action& a);
    /// The pointer of this frame (scripted or the mouse), also handed to ImGui.
    pointer_state read_pointer();
    void move_camera(const pointer_state& now);
    void refresh_particles();
    void draw_scene();
    /// The part of the window the scene is drawn in, left of the panel: x, y, width, height.
    std::array<int, 4> scene_viewport() const;
    void draw_panel();
    /// A panel button, its rectangle kept for the `button` script action.
    bool panel_button(const char* label);
    void draw_legend();
    /// A ring around the picked particle and smaller ones around its neighbors.
    void draw_pick_marker();
    /// The picked particle's search and the cell grid block (toggle) for this frame's pointer,
    /// recomputed when the snapshot, the pick or the particle under the pointer changes.
    void refresh_search(const pointer_state& now);
    void draw_parameters();

    // Colliders by hand (viewer_colliders.cpp).
    /// A left press: grabs (and selects) the collider under the pointer; false when none.
    bool grab_collider(const pointer_state& now);
    /// While held: moves the collider with the pointer since the last frame, in the view plane
    /// through its center, or with Shift along the view direction.
    void drag_collider(const pointer_state& now);
    void release_collider();
    void add_collider(sim::shape kind);
    void delete_collider();
    /// Turns the selected collider about the view direction, counterclockwise as seen.
    void rotate_collider(double degrees);
    /// The colliders as edited go to the simulation at once (held: the one being dragged).
    void send_colliders(bool held);
    /// The panel's colliders section: the list, Add sphere, Add box, Delete, Rotate.
    void draw_colliders();
    /// The Profile section: the live per-stage timing bar, steps and frames per second, and
    /// "Capture profile".
    void draw_profile();
    void capture_profile(int steps, const std::string& path);
    /// The Scene section: a control for every key of the scene's JSON with no control elsewhere.
    void draw_scene_keys();
    /// Sets a scene key by its path (sim::with_scene_key) for the panel and `set_scene` scripts:
    /// solver parameters and gravity reach the running simulation as their own controls send
    /// them, every other key waits for Reset. Throws frnn::error when the key or value is bad.
    void set_scene_key(const std::string& path, const std::string& value_json);
    void write_state(const std::string& path) const;
    /// The window's pixels as drawn this frame (the back buffer), top row first.
    sim::image window_pixels() const;
    void save_screenshot(const std::string& path) const;
    /// Record: starts or stops recording (recorder.hpp); the outcome goes to the panel.
    void start_recording(const std::string& dir);
    void stop_recording();
    void record_frame();
    void save_scene(const std::string& path);
    void switch_scene(sim::scene next);
    /// Shows `next` in the panel and frames it (the simulation thread already has it).
    void adopt_scene(sim::scene next);
    /// The Apply-scene choices and the gravity control show scene_.
    void show_scene_choices();
    void save_state(const std::string& path);
    void load_state(const std::string& path);
    void toggle_play();
    void step();
    void reset();

    view_options opt_;
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<sim_runner> runner_;
    std::unique_ptr<particle_renderer> particles_;
    std::unique_ptr<line_renderer> lines_;
    camera cam_;
    std::optional<script> script_;
    std::size_t next_action_ = 0;
    long frame_ = 0;

    // What the panel shows and edits; the simulation thread follows by commands, and takes the
    // keys that wait for Reset (reset_pending_) when it restarts.
    sim::scene scene_;
    bool reset_pending_ = false;
    std::string scene_label_;
    int chosen_scene_ = 0, chosen_solver_ = 0, chosen_dim_ = 3, chosen_particles_ = 0;
    bool playing_ = true;  // lockstep play state (decoupled: the runner's)
    field field_ = field::speed;
    bool auto_range_ = true;
    float range_min_ = 0, range_max_ = 1, shown_min_ = 0, shown_max_ = 1;
    float time_scale_ = 1;
    std::array<float, 3> gravity_{0, 0, 0};
    std::string save_path_ = "scene-saved.json", state_path_ = "viewer-checkpoint.bin", message_;

    sim::particle_snapshot snapshot_;
    std::vector<float> values_;
    double lines_time_ = -1;
    bool scene_changed_ = true;

    // Pointer: scripted (under a script) or the real mouse; who owns the current drag.
    std::optional<pointer_state> scripted_;
    std::vector<std::pair<long, pointer_state>> pointer_events_;  // (frame, state), sorted
    pointer_state last_pointer_;
    int drag_button_ = -1;
    pointer_state press_;  // where the camera's drag began: a release there is a click (picks)
    std::optional<std::size_t> picked_;  // particle id
    std::optional<std::size_t> selected_collider_;  // index in scene_.colliders
    bool holding_collider_ = false;                 // the left drag moves it
    std::unique_ptr<line_renderer> selection_lines_;  // its outline, drawn over the particles

    // The search made visible (search_view.hpp): the picked particle's cells and neighbors, and
    // with the cell grid toggle the block of cells a search visits around the particle under
    // the pointer (the picked one when the pointer is on none).
    std::unique_ptr<line_renderer> search_lines_;
    bool show_cell_grid_ = false;
    particle_search search_;
    std::vector<cell_index> grid_cells_;
    std::optional<std::size_t> grid_center_;
    bool search_stale_ = true;
    double scroll_ = 0;
    std::map<std::string, std::array<float, 4>> buttons_;  // panel button rects by label
    std::array<float, 4> legend_rect_{0, 0, 0, 0};

    // Decoupling and timing.
    std::uint64_t last_started_ = 0;
    long frames_in_step_ = 0, max_frames_in_step_ = 0;
    double upload_seconds_ = 0, draw_seconds_ = 0, wait_seconds_ = 0;
    long timed_frames_ = 0;
    std::vector<double> frame_ms_;  // --timing: each frame's wall time, swap included
    std::string script_error_;

    // Profiling: drawing time per frame (averaged like the stages'), steps per second over
    // windows of half a second, the capture's steps and file.
    double draw_ms_ = 0, steps_per_second_ = 0;
    std::chrono::steady_clock::time_point rate_start_ = std::chrono::steady_clock::now();
    std::uint64_t rate_steps_ = 0;
    int profile_steps_ = 20;
    std::string profile_path_ = "profile.json";

    recorder recorder_;
    std::string record_dir_ = "recording";
};

}  // namespace frnn::view
