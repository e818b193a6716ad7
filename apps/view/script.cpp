#include "script.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "frnn/error.hpp"

namespace frnn::view {
namespace {
using json = nlohmann::json;

class action_reader {
public:
    action_reader(const json& j, std::string where) : j_(j), where_(std::move(where)) {}
    [[noreturn]] void fail(const std::string& what) const { throw error(where_ + ": " + what); }
    const json& need(const char* key) const {
        if (!j_.contains(key)) fail(std::string("missing key '") + key + "'");
        return j_.at(key);
    }
    double number(const char* key) const {
        const json& v = need(key);
        if (!v.is_number()) fail(std::string("key '") + key + "': expected a number, got " + v.dump());
        return v.get<double>();
    }
    double number_or(const char* key, double def) const { return j_.contains(key) ? number(key) : def; }
    std::string text(const char* key) const {
        const json& v = need(key);
        if (!v.is_string()) fail(std::string("key '") + key + "': expected a string, got " + v.dump());
        return v.get<std::string>();
    }
    template <std::size_t N>
    std::array<double, N> numbers(const char* key, std::size_t least = N) const {
        const json& v = need(key);
        if (!v.is_array() || v.size() < least || v.size() > N)
            fail(std::string("key '") + key + "': expected an array of " + std::to_string(N) + " numbers, got " + v.dump());
        std::array<double, N> r{};
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_number()) fail(std::string("key '") + key + "': expected numbers, got " + v.dump());
            r[i] = v[i].get<double>();
        }
        return r;
    }
    int button() const {
        if (!j_.contains("button")) return 0;
        const std::string b = text("button");
        if (b == "left") return 0;
        if (b == "right") return 1;
        if (b == "middle") return 2;
        fail("key 'button': expected \"left\", \"right\" or \"middle\", got \"" + b + "\"");
    }
    bool shift() const {
        if (!j_.contains("modifier")) return false;
        const std::string m = text("modifier");
        if (m != "shift") fail("key 'modifier': expected \"shift\", got \"" + m + "\"");
        return true;
    }

private:
    const json& j_;
    std::string where_;
};

script_action read_action(const json& j, const std::string& where) {
    if (!j.is_object()) throw error(where + ": expected an object, got " + j.dump());
    const action_reader r(j, where);
    script_action a;
    const json& f = r.need("frame");
    if (!f.is_number_integer() || f.get<std::int64_t>() < 0) r.fail("key 'frame': expected an integer >= 0, got " + f.dump());
    a.frame = f.get<std::int64_t>();
    a.what = r.text("do");
    a.where = where;
    const std::string& w = a.what;
    if (w == "play" || w == "pause" || w == "step" || w == "reset" || w == "reset_view") {
    } else if (w == "set") {
        a.name = r.text("name");
        a.value = r.number("value");
    } else if (w == "set_scene") {
        a.name = r.text("key");
        a.value_json = r.need("value").dump();
    } else if (w == "gravity") {
        a.vec = r.numbers<3>("value");
    } else if (w == "time_scale") {
        a.value = r.number("value");
    } else if (w == "color") {
        a.text = r.text("field");
        if (j.contains("range")) {
            a.range = r.numbers<2>("range");
            a.has_range = true;
        }
    } else if (w == "camera") {
        a.vec = r.numbers<3>("target");
        a.distance = r.number("distance");
        a.yaw = r.number("yaw");
        a.pitch = r.number("pitch");
        a.fov = r.number_or("fov", 45);
    } else if (w == "key") {
        a.text = r.text("key");
    } else if (w == "click" || w == "scroll") {
        a.vec[0] = r.number("x");
        a.vec[1] = r.number("y");
        a.button = r.button();
        a.value = w == "scroll" ? r.number("steps") : 0;
        a.shift = w == "click" && r.shift();
    } else if (w == "drag") {
        const auto from = r.numbers<2>("from");
        a.vec = {from[0], from[1], 0};
        a.to = r.numbers<2>("to");
        a.button = r.button();
        a.shift = r.shift();
        a.frames = int(r.number_or("frames", 10));
        if (a.frames < 1) r.fail("key 'frames': expected at least 1");
    } else if (w == "button") {
        a.text = r.text("label");
    } else if (w == "record") {
        a.text = r.text("dir");
    } else if (w == "add_collider") {
        a.text = r.text("type");
        if (a.text != "sphere" && a.text != "box") r.fail("key 'type': expected \"sphere\" or \"box\", got \"" + a.text + "\"");
    } else if (w == "rotate_collider") {
        a.value = r.number("degrees");
    } else if (w == "stop_recording" || w == "delete_collider") {
    } else if (w == "capture_profile") {
        a.value = r.number("steps");
        if (a.value < 1 || a.value != std::floor(a.value)) r.fail("key 'steps': expected a whole number >= 1");
        a.text = r.text("path");
    } else if (w == "save_scene" || w == "save_state" || w == "load_state") {
        a.text = r.text("path");
    } else {
        r.fail("unknown action '" + w + "'");
    }
    return a;
}

}  // namespace

script load_script(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw error("cannot open script '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    json j;
    try {
        j = json::parse(ss.str());
    } catch (const json::exception& e) {
        throw error(path + ": not valid JSON: " + e.what());
    }
    if (!j.is_object() || !j.contains("actions") || !j.at("actions").is_array())
        throw error(path + ": expected {\"steps_per_frame\": S, \"actions\": [...]}");
    script s;
    if (j.contains("steps_per_frame")) {
        const json& v = j.at("steps_per_frame");
        if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 100000)
            throw error(path + ": key 'steps_per_frame': expected an integer in [0, 100000], got " + v.dump());
        s.steps_per_frame = v.get<int>();
    }
    for (std::size_t i = 0; i < j.at("actions").size(); ++i)
        s.actions.push_back(read_action(j.at("actions")[i], path + ": actions[" + std::to_string(i) + "]"));
    std::stable_sort(s.actions.begin(), s.actions.end(), [](const auto& a, const auto& b) { return a.frame < b.frame; });
    return s;
}

}  // namespace frnn::view
