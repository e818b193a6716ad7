// Every key of every shipped scene has a control: set by the `set_scene` script action (the
// code the panel's Scene section runs) to another valid value, it is in the scene the viewer
// saves. The keys are read from the shipped files, so a key a scene gains without a control
// fails here. Keys that wait for Reset take effect then, and only then.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "frnn/sim/scene.hpp"
#include "frnn/sim/scene_keys.hpp"
#include "sim/small_scene.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;
using json = nlohmann::json;

namespace {

/// Every leaf of j (neither an object nor an array of objects) with its path.
void leaves(const json& j, const std::string& path, std::vector<std::pair<std::string, json>>& out) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) leaves(*it, path.empty() ? it.key() : path + "." + it.key(), out);
    } else if (j.is_array() && !j.empty() && j[0].is_object()) {
        for (std::size_t i = 0; i < j.size(); ++i) leaves(j[i], path + "[" + std::to_string(i) + "]", out);
    } else {
        out.emplace_back(path, j);
    }
}

/// A number the parser accepts wherever it accepts x: a little larger, and not 0 (so max
/// stays above min, sizes positive, fractions at most 1 for the shipped values).
double nudged(double x) { return x * 1.1 + 0.01; }

/// Another value than v for the key at `path`, one the scene parser accepts.
json changed(const std::string& path, const json& v) {
    for (const auto& c : frnn::sim::scene_key_choices(path))
        if (c != v) return c;
    if (v.is_string()) return v.get<std::string>() + " (edited)";
    if (v.is_boolean()) return !v.get<bool>();
    if (v.is_number_integer()) {
        const auto n = v.get<std::int64_t>();
        return n > 1 ? n - 1 : n + 1;  // integer keys stay in range: dim 3 to 2, axis 0 to 1
    }
    if (v.is_number()) return nudged(v.get<double>());
    json a = json::array();
    for (const auto& x : v) a.push_back(nudged(x.get<double>()));
    return a;
}

/// Structural keys go last: a changed type gives its object other keys, a changed dim
/// flattens the scene's z components.
int order(const std::string& path) { return path == "dim" ? 2 : frnn::sim::scene_key_choices(path).empty() ? 0 : 1; }

/// Equal, numbers within rounding (collider angles are saved in degrees, kept in radians).
bool same(const json& a, const json& b) {
    if (a.is_number() && b.is_number()) return std::abs(a.get<double>() - b.get<double>()) <= 1e-12 * std::max(1.0, std::abs(a.get<double>()));
    if (a.is_array() && b.is_array() && a.size() == b.size()) {
        for (std::size_t i = 0; i < a.size(); ++i)
            if (!same(a[i], b[i])) return false;
        return true;
    }
    return a == b;
}

/// The value at a path in saved JSON ("colliders[0].center"), or null.
json at_path(const json& j, const std::string& path) {
    const json* at = &j;
    std::size_t i = 0;
    while (i < path.size()) {
        if (path[i] == '.') ++i;
        if (path[i] == '[') {
            const std::size_t close = path.find(']', i);
            const std::size_t k = std::stoul(path.substr(i + 1, close - i - 1));
            if (!at->is_array() || k >= at->size()) return nullptr;
            at = &(*at)[k];
            i = close + 1;
            continue;
        }
        const std::size_t end = std::min(path.find('.', i), path.find('[', i));
        const std::string key = path.substr(i, end - i);
        if (!at->is_object() || !at->contains(key)) return nullptr;
        at = &(*at)[key];
        i = std::min(end, path.size());
    }
    return *at;
}

/// The file the scene is saved to after the k-th key is set. Appended piece by piece: GCC 12
/// misreports `"k" + std::to_string(k)` as an overlapping copy (-Wrestrict, bug 105651).
std::string saved_file(std::size_t k) {
    std::string name = "k";
    name += std::to_string(k);
    name += ".json";
    return name;
}

}  // namespace

TEST(ViewerSceneKeys, EveryKeyOfEveryShippedSceneIsSetAndSaved) {
    for (const auto& name : frnn::sim::builtin_scene_names()) {
        std::vector<std::pair<std::string, json>> keys;
        leaves(json::parse(frnn::sim::builtin_scene_text(name)), "", keys);
        std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return order(a.first) < order(b.first); });
        // One run per scene: each key set, then the scene saved to a file of its own.
        json actions = json::array();
        for (std::size_t k = 0; k < keys.size(); ++k) {
            actions.push_back({{"frame", 1}, {"do", "set_scene"}, {"key", keys[k].first}, {"value", changed(keys[k].first, keys[k].second)}});
            actions.push_back({{"frame", 1}, {"do", "save_scene"}, {"path", saved_file(k)}});
        }
        const scratch_dir dir("viewer_scene_keys_" + name);
        write_text(dir / "script.json", json{{"steps_per_frame", 1}, {"actions", actions}}.dump());
        const auto r = run_viewer(dir, "--scene " + name + " --dim 3 --particles 300 --paused --script script.json --frames 2");
        ASSERT_EQ(r.code, 0) << name << ": " << r.err;
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const auto& [path, value] = keys[k];
            const json saved = read_json(dir / saved_file(k));
            const json want = changed(path, value);
            EXPECT_TRUE(same(at_path(saved, path), want)) << name << ": " << path << " saved as " << at_path(saved, path) << ", set to " << want;
        }
        EXPECT_NO_THROW(frnn::sim::load_scene((dir / saved_file(keys.size() - 1)).string())) << name;
    }
}

// A fluid block made shallower waits for Reset; Reset seeds the edited scene.
TEST(ViewerSceneKeys, GeometryTakesEffectOnReset) {
    const frnn::sim::scene s = small_scene("droplet", frnn::sim::solver_kind::viscoelastic, 2, 400);
    frnn::sim::scene edited = s;
    edited.fluid[0].max = {1, 0.1, 1};
    const frnn::sim::seeded_particles before = frnn::sim::seed(s), after = frnn::sim::seed(edited);
    ASSERT_NE(before.x, after.x);
    for (const bool reset : {false, true}) {
        const scratch_dir dir(reset ? "viewer_scene_key_reset" : "viewer_scene_key_pending");
        json actions = json::array({{{"frame", 1}, {"do", "set_scene"}, {"key", "fluid[0].max"}, {"value", {1, 0.1, 1}}}});
        if (reset) actions.push_back({{"frame", 1}, {"do", "reset"}});
        write_text(dir / "script.json", json{{"steps_per_frame", 1}, {"actions", actions}}.dump());
        const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 400 --paused --script script.json --frames 3 --state state.json");
        ASSERT_EQ(r.code, 0) << r.err;
        const json state = read_json(dir / "state.json");
        const frnn::sim::seeded_particles& want = reset ? after : before;
        ASSERT_EQ(state.at("particles").get<std::size_t>(), want.count) << "reset " << reset;
        const auto x = state.at("x").get<std::vector<float>>();
        for (std::size_t k = 0; k < want.count; ++k)
            for (std::size_t a = 0; a < 2; ++a)
                ASSERT_EQ(x[k * 3 + a], want.x[k * 2 + a]) << "reset " << reset << ", particle " << k;
        EXPECT_EQ(state.at("step"), 0);
    }
}
