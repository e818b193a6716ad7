// `--script FILE`: actions keyed by frame number, for tests and demos. The file is
// {"steps_per_frame": S, "actions": [{"frame": F, "do": WHAT, ...}, ...]}; with a script the
// viewer runs in lockstep, exactly S steps per drawn frame while playing. Actions:
//   play, pause, step, reset, reset_view                     the panel's buttons and keys
//   set {"name": "sph.alpha", "value": 0.2}                  a parameter of the table
//   set_scene {"key": "colliders[0].center", "value": [x, y, z]}   any scene key by its path,
//                                                            as the panel's Scene section sets it
//   gravity {"value": [x, y, z]}, time_scale {"value": s}
//   color {"field": "speed", "range": [lo, hi]}             fixed range; without "range": auto
//   camera {"target": [x,y,z], "distance": d, "yaw": deg, "pitch": deg, "fov": deg}
//   key {"key": "space"}                                     as if typed (see docs/VIEWER.md)
//   click {"x": px, "y": px, "button": "left", "modifier": "shift"}  press now, release next frame
//                                                            (left: selects a collider or picks a particle)
//   drag {"from": [x, y], "to": [x, y], "button": "left", "frames": k, "modifier": "shift"}
//                                                            (left from a collider: moves it)
//   scroll {"x": px, "y": px, "steps": s}
//   button {"label": "Reset"}                                clicks the panel button with that label
//   save_scene {"path": "out.json"}                          the scene JSON, for frnn sim
//   save_state {"path": "x.bin"}, load_state {"path": ...}   a checkpoint (frnn sim's format)
//   capture_profile {"steps": n, "path": "trace.json"}       a Chrome trace of the next n steps
//   record {"dir": "rec"}, stop_recording                    PNG frames and an MP4 (recorder.hpp)
//   add_collider {"type": "sphere"}                          as the panel's Add sphere / Add box
//   delete_collider, rotate_collider {"degrees": d}          the selected collider (an error if none)
// A bad file throws frnn::error naming the file, the action's index and what was expected.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace frnn::view {

struct script_action {
    std::int64_t frame = 0;
    std::string what;  ///< "play", "set", ...
    std::string where;  ///< "FILE: actions[i]", for messages
    std::string name, text;  ///< set: the parameter; set_scene: the key path; key: the key; button: its label; color: the field; add_collider: the type; save_scene, save_state, load_state, capture_profile: the path; record: the folder
    std::string value_json;  ///< set_scene: the value as JSON text
    double value = 0;  ///< set, time_scale, scroll steps, capture_profile steps, rotate_collider degrees
    std::array<double, 3> vec{0, 0, 0};  ///< gravity, camera target, click/scroll position (x, y)
    std::array<double, 2> to{0, 0};      ///< drag end
    std::array<double, 2> range{0, 0};
    bool has_range = false;
    double distance = 0, yaw = 0, pitch = 0, fov = 45;
    int button = 0;    ///< 0 left, 1 right, 2 middle
    int frames = 10;   ///< drag duration
    bool shift = false;  ///< click, drag: with Shift held
};

struct script {
    int steps_per_frame = 1;
    std::vector<script_action> actions;  ///< sorted by frame, stable
};

script load_script(const std::string& path);

}  // namespace frnn::view
