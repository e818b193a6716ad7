// Scene keys by path: the scene's JSON edited at one path and parsed again; a changed type
// converts the block's or collider's geometry first, since each type writes other keys.
#include "frnn/sim/scene_keys.hpp"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include "frnn/error.hpp"
#include "frnn/sim/parameters.hpp"

namespace frnn::sim {
namespace {
using json = nlohmann::json;

/// One step of a path: an object's key, or an array's index when `key` is empty.
struct path_step {
    std::string key;
    std::size_t index = 0;
};

/// "colliders[0].center" as {colliders}, {[0]}, {center}; nothing for a malformed path.
std::vector<path_step> split_path(std::string_view path) {
    std::vector<path_step> steps;
    std::size_t i = 0;
    while (i < path.size()) {
        if (path[i] == '[') {
            const std::size_t close = path.find(']', i);
            const std::string_view digits = path.substr(i + 1, close == std::string_view::npos ? 0 : close - i - 1);
            if (digits.empty() || digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
                return {};
            steps.push_back({"", std::stoul(std::string(digits))});
            i = close + 1;
            continue;
        }
        if (!steps.empty()) {
            if (path[i] != '.') return {};
            ++i;
        }
        std::size_t end = i;
        while (end < path.size() && path[end] != '.' && path[end] != '[') ++end;
        if (end == i) return {};
        steps.push_back({std::string(path.substr(i, end - i)), 0});
        i = end;
    }
    return steps;
}

/// The value at `steps` inside j, or nullptr.
json* find(json& j, const std::vector<path_step>& steps) {
    json* at = &j;
    for (const auto& s : steps) {
        if (!s.key.empty() && at->is_object() && at->contains(s.key)) at = &(*at)[s.key];
        else if (s.key.empty() && at->is_array() && s.index < at->size()) at = &(*at)[s.index];
        else return nullptr;
    }
    return at;
}

/// The position of `name` in `names`, or names.size().
std::size_t position(const std::vector<std::string>& names, const json& name) {
    if (!name.is_string()) return names.size();
    return std::size_t(std::find(names.begin(), names.end(), name.get<std::string>()) - names.begin());
}

/// `steps` names "section[i].type"; i is returned in `index`.
bool is_type_of(const std::vector<path_step>& steps, const char* section, std::size_t& index) {
    if (steps.size() != 3 || steps[0].key != section || !steps[1].key.empty() || steps[2].key != "type") return false;
    index = steps[1].index;
    return true;
}

void convert(fluid_block& b, fluid_block::kind_t to, int dim) {
    if (b.kind == to) return;
    if (to == fluid_block::kind_t::sphere) {
        double radius = std::numeric_limits<double>::max();
        for (std::size_t a = 0; a < 3; ++a) {
            b.center[a] = 0.5 * (b.min[a] + b.max[a]);
            if (int(a) < dim) radius = std::min(radius, 0.5 * (b.max[a] - b.min[a]));
        }
        b.radius = radius;
    } else {
        for (std::size_t a = 0; a < 3; ++a) b.min[a] = b.center[a] - b.radius, b.max[a] = b.center[a] + b.radius;
    }
    b.kind = to;
}

void convert(collider& c, shape to) {
    if (c.kind == to) return;
    const auto bounded = [](double half) { return half < 1e20; };  // not a flattened axis of a 2D scene
    if (c.kind == shape::box && to == shape::sphere) {
        double radius = std::numeric_limits<double>::max();
        for (double h : c.half)
            if (bounded(h)) radius = std::min(radius, h);
        c.radius = radius;
    }
    if (c.kind == shape::sphere && to == shape::box)
        for (double& h : c.half)
            if (bounded(h)) h = c.radius;
    if (to == shape::plane) c.inside = false;  // a plane's fluid side is given by its normal
    c.kind = to;
}

}  // namespace

std::vector<std::string> scene_key_choices(std::string_view path) {
    const std::vector<path_step> steps = split_path(path);
    std::size_t index = 0;
    if (steps.size() == 1 && steps[0].key == "solver") return solver_names();
    if (is_type_of(steps, "fluid", index)) return fluid_block_types();
    if (is_type_of(steps, "colliders", index)) return collider_types();
    const parameter* p = find_parameter(path);
    return p ? p->choices : std::vector<std::string>{};
}

scene with_scene_key(const scene& s, std::string_view path, std::string_view value, const std::string& origin) {
    const std::string where = origin + ": key '" + std::string(path) + "'";
    json v;
    try {
        v = json::parse(value);
    } catch (const json::exception&) {
        throw error(where + ": the value is not JSON: " + std::string(value));
    }
    const std::vector<path_step> steps = split_path(path);
    scene base = s;
    std::size_t i = 0;
    if (is_type_of(steps, "fluid", i) && i < base.fluid.size() && position(fluid_block_types(), v) < fluid_block_types().size())
        convert(base.fluid[i], fluid_block::kind_t(position(fluid_block_types(), v)), base.dim);
    if (is_type_of(steps, "colliders", i) && i < base.colliders.size() && position(collider_types(), v) < collider_types().size())
        convert(base.colliders[i], shape(position(collider_types(), v)));
    json j = json::parse(scene_to_json(base));
    json* at = steps.empty() ? nullptr : find(j, steps);
    if (!at) throw error(origin + ": no key '" + std::string(path) + "' in the scene");
    *at = std::move(v);
    return parse_scene(j.dump(), origin);
}

}  // namespace frnn::sim
