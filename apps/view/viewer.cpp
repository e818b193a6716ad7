#include "viewer.hpp"

// gl.hpp first: it declares the OpenGL prototypes, which GLFW's own include of GL/gl.h omits.
#include "gl.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "frnn/io/atomic_file.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"
#include "collider_editing.hpp"
#include "line_renderer.hpp"
#include "median.hpp"
#include "particle_renderer.hpp"
#include "picking.hpp"

namespace frnn::view {
namespace {

std::string glfw_error_text;
void remember_glfw_error(int, const char* description) { glfw_error_text = description ? description : "unknown"; }

viewer* owner(GLFWwindow* w) { return static_cast<viewer*>(glfwGetWindowUserPointer(w)); }

void key_callback(GLFWwindow* w, int key, int, int action, int) {
    if (action == GLFW_PRESS && !ImGui::GetIO().WantCaptureKeyboard) owner(w)->on_key(key);
}
void scroll_callback(GLFWwindow* w, double, double dy) { owner(w)->on_scroll(dy); }

int key_code(const std::string& name) {
    if (name == "space") return GLFW_KEY_SPACE;
    if (name == "escape") return GLFW_KEY_ESCAPE;
    if (name == "delete") return GLFW_KEY_DELETE;
    if (name == "[") return GLFW_KEY_LEFT_BRACKET;
    if (name == "]") return GLFW_KEY_RIGHT_BRACKET;
    if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z') return GLFW_KEY_A + (name[0] - 'a');
    return -1;
}

using clock_type = std::chrono::steady_clock;
double seconds_since(clock_type::time_point t0) { return std::chrono::duration<double>(clock_type::now() - t0).count(); }

}  // namespace

viewer::viewer(const sim::scene& s, const view_options& o) : opt_(o), scene_(s) {
    if (!opt_.script_file.empty()) {
        script_ = load_script(opt_.script_file);
        // Clicks and drags become pointer states at frames.
        for (const auto& a : script_->actions) {
            pointer_state p;
            p.x = a.vec[0], p.y = a.vec[1];
            p.shift = a.shift;
            if (a.what == "click") {
                p.down[std::size_t(a.button)] = true;
                pointer_events_.emplace_back(a.frame, p);
                p.down[std::size_t(a.button)] = false;
                pointer_events_.emplace_back(a.frame + 1, p);
            } else if (a.what == "drag") {
                for (int k = 0; k <= a.frames; ++k) {
                    const double f = double(k) / a.frames;
                    p.x = a.vec[0] + f * (a.to[0] - a.vec[0]);
                    p.y = a.vec[1] + f * (a.to[1] - a.vec[1]);
                    p.down[std::size_t(a.button)] = true;
                    pointer_events_.emplace_back(a.frame + k, p);
                }
                p.down[std::size_t(a.button)] = false;
                pointer_events_.emplace_back(a.frame + a.frames + 1, p);
            }
        }
        std::stable_sort(pointer_events_.begin(), pointer_events_.end(), [](auto& a, auto& b) { return a.first < b.first; });
        scripted_ = pointer_state{};
    }
    runner_ = std::make_unique<sim_runner>(scene_, opt_.threads, opt_.slow_step_ms);

    glfwSetErrorCallback(remember_glfw_error);
    if (!glfwInit()) throw error("cannot open a window: " + glfw_error_text);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, script_ ? GLFW_FALSE : GLFW_TRUE);  // scripts address fixed pixels
    window_ = glfwCreateWindow(opt_.width, opt_.height, "frnn view", nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw error("cannot create an OpenGL 3.3 core window: " + glfw_error_text);
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(opt_.frames > 0 ? 0 : 1);
    glfwSetWindowUserPointer(window_, this);
    // Installed before ImGui's, which calls them after its own.
    glfwSetKeyCallback(window_, key_callback);
    glfwSetScrollCallback(window_, scroll_callback);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    particles_ = std::make_unique<particle_renderer>();
    lines_ = std::make_unique<line_renderer>();
    search_lines_ = std::make_unique<line_renderer>();
    selection_lines_ = std::make_unique<line_renderer>();

    const auto names = sim::builtin_scene_names();
    chosen_scene_ = int(std::find(names.begin(), names.end(), scene_.name) - names.begin());
    scene_label_ = opt_.scene_file.empty() ? scene_.name : opt_.scene_file;
    if (!opt_.scene_file.empty()) chosen_scene_ = int(names.size());  // the file, listed after the shipped scenes
    adopt_scene(scene_);
    playing_ = !opt_.paused;
    if (!script_) runner_->set_playing(playing_);
}

viewer::~viewer() {
    runner_.reset();  // stop the simulation thread first
    particles_.reset();
    lines_.reset();
    search_lines_.reset();
    selection_lines_.reset();
    if (window_) {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(window_);
    }
#ifndef __SANITIZE_ADDRESS__
    glfwTerminate();
#else
    // The sanitizer tree leaves GLFW up: glfwTerminate unloads the GL driver and X extension
    // libraries, after which LeakSanitizer sees their exit-time allocations as unreachable
    // blocks of an unknown module that no suppression can name; loaded, they stay reachable
    // and the viewer's own allocations are still checked.
#endif
}

void viewer::on_key(int key) {
    switch (key) {
    case GLFW_KEY_SPACE: toggle_play(); break;
    case GLFW_KEY_S: step(); break;
    case GLFW_KEY_R: reset(); break;
    case GLFW_KEY_C: cam_.reset(); break;
    case GLFW_KEY_G: show_cell_grid_ = !show_cell_grid_, search_stale_ = true; break;
    case GLFW_KEY_LEFT_BRACKET: rotate_collider(rotate_step_degrees); break;
    case GLFW_KEY_RIGHT_BRACKET: rotate_collider(-rotate_step_degrees); break;
    case GLFW_KEY_DELETE: delete_collider(); break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
    default: break;
    }
}

void viewer::on_scroll(double steps) { scroll_ += steps; }

void viewer::toggle_play() {
    playing_ = !playing_;
    if (!script_) runner_->set_playing(playing_);
}

void viewer::step() {
    playing_ = false;
    if (!script_) runner_->set_playing(false);
    runner_->step_once();
}

// The scene as edited in the panel, reseeded: keys that wait for Reset take effect.
void viewer::reset() {
    runner_->set_scene(scene_);
    reset_pending_ = false;
}

void viewer::switch_scene(sim::scene next) {
    runner_->set_scene(next);
    adopt_scene(std::move(next));
}

void viewer::adopt_scene(sim::scene next) {
    scene_ = std::move(next);
    reset_pending_ = false;
    selected_collider_.reset(), holding_collider_ = false;
    show_scene_choices();
    cam_.frame({float(scene_.domain_min[0]), float(scene_.domain_min[1]), float(scene_.domain_min[2])},
               {float(scene_.domain_max[0]), float(scene_.domain_max[1]), float(scene_.domain_max[2])}, scene_.dim == 2);
    scene_changed_ = true;
}

void viewer::show_scene_choices() {
    chosen_solver_ = scene_.solver == sim::solver_kind::sph ? 1 : 0;
    chosen_dim_ = scene_.dim;
    chosen_particles_ = int(scene_.target_particles());
    for (int a = 0; a < 3; ++a) gravity_[std::size_t(a)] = float(scene_.gravity[std::size_t(a)]);
}

// The scene as edited, keys waiting for Reset included.
void viewer::save_scene(const std::string& path) {
    try {
        io::write_file_atomically(path, sim::scene_to_json(scene_));
        message_ = "saved " + path;
    } catch (const std::exception& e) {
        message_ = e.what();
        if (script_) script_error_ = e.what();
    }
}

void viewer::capture_profile(int steps, const std::string& path) {
    runner_->capture_profile(steps, path);
    message_.clear();
}

void viewer::save_state(const std::string& path) {
    runner_->save_checkpoint(path);
    message_ = "saving the state to " + path;
}

void viewer::load_state(const std::string& path) {
    runner_->load_checkpoint(path);
    message_ = "loading the state from " + path;
}

void viewer::apply(const script_action& a) {
    const std::string& w = a.what;
    if (w == "play") {
        playing_ = true;
    } else if (w == "pause") {
        playing_ = false;
    } else if (w == "step") {
        step();
    } else if (w == "reset") {
        reset();
    } else if (w == "reset_view") {
        cam_.reset();
    } else if (w == "set") {
        const sim::parameter* p = sim::find_parameter(a.name);
        if (!p) throw error(opt_.script_file + ": frame " + std::to_string(a.frame) + ": no parameter '" + a.name + "'");
        try {
            sim::check_parameter_value(*p, a.value);
        } catch (const error& e) {
            throw error(opt_.script_file + ": frame " + std::to_string(a.frame) + ": " + e.what());
        }
        p->set(scene_, a.value);
        runner_->set_parameter(*p, a.value);
    } else if (w == "set_scene") {
        try {
            set_scene_key(a.name, a.value_json);
        } catch (const error& e) {
            throw error(a.where + " (frame " + std::to_string(a.frame) + "): set_scene " + a.name + " = " + a.value_json + ": " + e.what());
        }
    } else if (w == "gravity") {
        gravity_ = {float(a.vec[0]), float(a.vec[1]), float(a.vec[2])};
        scene_.gravity = a.vec;
        runner_->set_gravity(a.vec);
    } else if (w == "time_scale") {
        time_scale_ = float(a.value);
        runner_->set_time_scale(a.value);
    } else if (w == "color") {
        if (!field_by_name(a.text, field_))
            throw error(opt_.script_file + ": frame " + std::to_string(a.frame) + ": no field '" + a.text + "'");
        auto_range_ = !a.has_range;
        if (a.has_range) range_min_ = float(a.range[0]), range_max_ = float(a.range[1]);
        scene_changed_ = true;  // re-upload the values
    } else if (w == "camera") {
        cam_.set_orbit({float(a.vec[0]), float(a.vec[1]), float(a.vec[2])}, float(a.distance), float(a.yaw), float(a.pitch),
                       float(a.fov));
    } else if (w == "key") {
        const int k = key_code(a.text);
        if (k < 0) throw error(opt_.script_file + ": frame " + std::to_string(a.frame) + ": unknown key '" + a.text + "'");
        on_key(k);
    } else if (w == "scroll") {
        scroll_ += a.value;
        if (scripted_) scripted_->x = a.vec[0], scripted_->y = a.vec[1];
    } else if (w == "button") {
        const auto it = buttons_.find(a.text);
        if (it == buttons_.end())
            throw error(opt_.script_file + ": frame " + std::to_string(a.frame) + ": no panel button '" + a.text +
                        "' (buttons exist from frame 1; Play and Pause share one)");
        // A real click on the button's center: press this frame, release the next.
        pointer_state p;
        p.x = 0.5 * (it->second[0] + it->second[2]);
        p.y = 0.5 * (it->second[1] + it->second[3]);
        p.down[0] = true;
        pointer_events_.insert(pointer_events_.begin(), {frame_, p});
        p.down[0] = false;
        pointer_events_.insert(pointer_events_.begin() + 1, {frame_ + 1, p});
        std::stable_sort(pointer_events_.begin(), pointer_events_.end(), [](auto& x, auto& y) { return x.first < y.first; });
    } else if (w == "add_collider") {
        add_collider(a.text == "box" ? sim::shape::box : sim::shape::sphere);
    } else if (w == "delete_collider" || w == "rotate_collider") {
        if (!selected_collider_)
            throw error(a.where + " (frame " + std::to_string(a.frame) + "): " + w + ": no collider is selected");
        if (w == "delete_collider") delete_collider();
        else rotate_collider(a.value);
    } else if (w == "record") {
        start_recording(a.text);
    } else if (w == "stop_recording") {
        stop_recording();
    } else if (w == "capture_profile") {
        capture_profile(int(a.value), a.text);
    } else if (w == "save_scene") {
        save_scene(a.text);
    } else if (w == "save_state") {
        save_state(a.text);
    } else if (w == "load_state") {
        load_state(a.text);
    }
}

void viewer::apply_actions() {
    if (!script_) return;
    while (next_action_ < script_->actions.size() && script_->actions[next_action_].frame <= frame_) apply(script_->actions[next_action_++]);
    while (!pointer_events_.empty() && pointer_events_.front().first <= frame_) {
        scripted_ = pointer_events_.front().second;
        pointer_events_.erase(pointer_events_.begin());
    }
}

pointer_state viewer::read_pointer() {
    pointer_state now;
    if (scripted_) {
        now = *scripted_;
        // ImGui reads the pointer from io; a script's pointer replaces the (absent) mouse.
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(float(now.x), float(now.y));
        for (int b = 0; b < 3; ++b) io.MouseDown[b] = now.down[std::size_t(b)];
    } else {
        glfwGetCursorPos(window_, &now.x, &now.y);
        for (int b = 0; b < 3; ++b) now.down[std::size_t(b)] = glfwGetMouseButton(window_, b) == GLFW_PRESS;
        now.shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    }
    return now;
}

void viewer::move_camera(const pointer_state& now) {
    // After ImGui::NewFrame, which decides from this frame's pointer whether ImGui wants it.
    const bool imgui_wants = ImGui::GetIO().WantCaptureMouse;
    // The camera moves by the pointer's motion since the last frame of a drag already under
    // way: where the pointer was before the press (a jump, under a script) does not count.
    const int dragging = drag_button_;
    const float dx = float(now.x - last_pointer_.x), dy = float(now.y - last_pointer_.y);
    if (dragging == 0 && holding_collider_) drag_collider(now);
    else if (dragging == 0 && !cam_.plane_view()) cam_.orbit(dx, dy);
    else if (dragging >= 0) cam_.pan(dx, dy, scene_viewport()[3]);
    if (dragging < 0) {
        // A drag belongs to the scene when it starts outside the panel: a left one to the
        // collider under the pointer, else to the camera.
        for (int b = 0; b < 3; ++b)
            if (now.down[std::size_t(b)] && !last_pointer_.down[std::size_t(b)] && !imgui_wants) {
                drag_button_ = b, press_ = now;
                holding_collider_ = b == 0 && grab_collider(now);
            }
    } else if (!now.down[std::size_t(dragging)]) {
        // A left press on no collider released where it began (within 3 px) is a click: it
        // picks a particle and leaves no collider selected.
        if (dragging == 0 && !holding_collider_ && std::hypot(now.x - press_.x, now.y - press_.y) <= 3) {
            int w = 0, h = 0;
            glfwGetFramebufferSize(window_, &w, &h);
            picked_ = pick_particle(snapshot_, float(0.5 * snapshot_.spacing), cam_, scene_viewport(), h, now.x, now.y);
            search_stale_ = true;
            if (selected_collider_) selected_collider_.reset(), scene_changed_ = true;
        }
        if (holding_collider_) release_collider();
        drag_button_ = -1;
    }
    if (scroll_ != 0 && !imgui_wants) cam_.zoom(float(scroll_));
    scroll_ = 0;
    last_pointer_ = now;
}

void viewer::refresh_particles() {
    const bool fresh = runner_->take_snapshot(snapshot_);
    if (!fresh && !scene_changed_ && !auto_range_) return;
    const auto t0 = clock_type::now();
    if (fresh || scene_changed_) {
        field_values(snapshot_, field_, values_);
        if (auto_range_ && !values_.empty()) {
            const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
            shown_min_ = *lo, shown_max_ = *hi;
        }
        particles_->upload(snapshot_.x, values_);
        search_stale_ = true;
        if (snapshot_.time != lines_time_ || scene_changed_) {
            lines_->upload(scene_lines(scene_, snapshot_.time));  // as edited: what Reset will run
            selection_lines_->upload(selection_outline(scene_, snapshot_.time, selected_collider_));
            lines_time_ = snapshot_.time;
        }
        scene_changed_ = false;
    }
    if (!auto_range_) shown_min_ = range_min_, shown_max_ = range_max_;
    upload_seconds_ += seconds_since(t0);
}

std::array<int, 4> viewer::scene_viewport() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    const int panel = int(panel_width);
    return {0, 0, w > 2 * panel ? w - panel : w, std::max(h, 1)};
}

void viewer::draw_scene() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    glViewport(0, 0, w, h);
    glClearColor(0.08f, 0.09f, 0.11f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const auto vp = scene_viewport();
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    glEnable(GL_DEPTH_TEST);
    const float aspect = float(vp[2]) / float(vp[3]);
    const mat4 view = cam_.view(), projection = cam_.projection(aspect);
    lines_->draw(multiply(projection, view));
    particles_->draw(view, projection, float(0.5 * snapshot_.spacing), shown_min_, shown_max_);
    glDisable(GL_DEPTH_TEST);
    search_lines_->draw(multiply(projection, view));  // over the particles: the cells hold them
    selection_lines_->draw(multiply(projection, view));  // a collider in the fluid shows too
    glViewport(0, 0, w, h);
}

void viewer::frame() {
    glfwPollEvents();
    apply_actions();
    const auto t_wait = clock_type::now();
    if (script_) {
        if (playing_ && script_->steps_per_frame > 0) runner_->run_steps(script_->steps_per_frame);
        else runner_->wait_idle();
        const std::string e = runner_->last_error();
        if (!e.empty()) script_error_ = e;
    } else if (runner_->playing() != playing_) {
        playing_ = runner_->playing();  // a failing step paused the run
    }
    wait_seconds_ += seconds_since(t_wait);
    sim::scene loaded;
    if (runner_->take_loaded_scene(loaded)) adopt_scene(std::move(loaded));  // a checkpoint's scene
    refresh_particles();

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    const pointer_state pointer = read_pointer();
    ImGui::NewFrame();
    move_camera(pointer);
    refresh_search(pointer);
    draw_panel();
    draw_legend();
    draw_pick_marker();
    ImGui::Render();

    const auto t_draw = clock_type::now();
    draw_scene();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (opt_.timing) glFinish();
    const double drawn = seconds_since(t_draw);
    draw_seconds_ += drawn;
    draw_ms_ = timed_frames_ == 0 ? 1e3 * drawn : 0.95 * draw_ms_ + 0.05 * 1e3 * drawn;
    ++timed_frames_;
    const double window = seconds_since(rate_start_);
    if (window >= 0.5) {
        const std::uint64_t steps = runner_->started_steps();
        steps_per_second_ = double(steps - rate_steps_) / window;
        rate_steps_ = steps, rate_start_ = clock_type::now();
    }
    if (recorder_.recording()) record_frame();

    // Frames drawn while one step runs (the decoupling test); a step's index tells them apart.
    const std::uint64_t started = runner_->started_steps();
    if (runner_->in_step() && started == last_started_) {
        max_frames_in_step_ = std::max(max_frames_in_step_, ++frames_in_step_);
    } else {
        frames_in_step_ = runner_->in_step() ? 1 : 0;
        last_started_ = started;
    }
}

int viewer::run() {
    while (!glfwWindowShouldClose(window_)) {
        const auto t_frame = clock_type::now();
        frame();
        ++frame_;
        const bool last = opt_.frames > 0 && frame_ >= opt_.frames;
        if (last && !opt_.screenshot_file.empty()) save_screenshot(opt_.screenshot_file);
        glfwSwapBuffers(window_);
        if (opt_.timing) frame_ms_.push_back(1e3 * seconds_since(t_frame));
        if (last || !script_error_.empty()) break;
    }
    runner_->set_playing(false);
    runner_->wait_idle();  // the last frame's commands (a released collider) reach the state
    if (recorder_.recording()) stop_recording();
    if (!opt_.state_file.empty()) write_state(opt_.state_file);
    if (opt_.timing && timed_frames_ > 0)
        std::printf("frnn-view: %zu particles, %ld frames: simulation %.2f ms/step, copy %.2f ms/snapshot, "
                    "upload %.2f ms/frame, drawing %.2f ms/frame\n",
                    snapshot_.n, timed_frames_, runner_->mean_step_ms(), runner_->mean_copy_ms(),
                    1e3 * upload_seconds_ / double(timed_frames_), 1e3 * draw_seconds_ / double(timed_frames_));
    if (opt_.timing && !frame_ms_.empty())
        std::printf("frnn-view: median frame %.2f ms (%zu frames), median step %.2f ms\n", median(frame_ms_), frame_ms_.size(),
                    runner_->median_step_ms());
    if (!script_error_.empty()) {
        std::fprintf(stderr, "frnn-view: error: %s\n", script_error_.c_str());
        return 1;
    }
    return 0;
}

sim::image viewer::window_pixels() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    sim::image img;
    img.width = w, img.height = h;
    std::vector<std::uint8_t> rows(std::size_t(w) * std::size_t(h) * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    img.rgb.resize(rows.size());
    const std::size_t stride = std::size_t(w) * 3;
    for (int y = 0; y < h; ++y)  // OpenGL's rows go bottom-up, the image's top-down
        std::copy_n(rows.data() + std::size_t(h - 1 - y) * stride, stride, img.rgb.data() + std::size_t(y) * stride);
    return img;
}

void viewer::save_screenshot(const std::string& path) const { io::write_file_atomically(path, sim::encode_png(window_pixels())); }

void viewer::start_recording(const std::string& dir) {
    try {
        if (recorder_.recording()) stop_recording();
        recorder_.start(dir);
        message_ = "recording to " + dir;
    } catch (const std::exception& e) {
        message_ = e.what();
        if (script_) script_error_ = e.what();
    }
}

void viewer::stop_recording() {
    if (!recorder_.recording()) return;
    try {
        message_ = "recorded " + recorder_.stop();
    } catch (const std::exception& e) {
        message_ = e.what();
        if (script_) script_error_ = e.what();
    }
}

// A frame that cannot be written ends the recording (a full disk must not fail every frame).
void viewer::record_frame() {
    try {
        recorder_.add(window_pixels());
    } catch (const std::exception& e) {
        message_ = e.what();
        if (script_) script_error_ = e.what();
        stop_recording();
    }
}

}  // namespace frnn::view
