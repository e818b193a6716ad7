// A scene written back as JSON in the parser's own format, so a scene edited live (in the
// viewer) can be saved and run by `frnn sim`. Solver sections go through the parameter table.
#include <nlohmann/json.hpp>

#include "frnn/sim/parameters.hpp"
#include "frnn/sim/scene.hpp"

namespace frnn::sim {
namespace {
using json = nlohmann::json;

constexpr double degrees_per_radian = 180 / 3.14159265358979323846;

json vector_json(const vec3& v) { return json::array({v[0], v[1], v[2]}); }

json block_json(const fluid_block& b) {
    json j;
    if (b.kind == fluid_block::kind_t::box) {
        j["type"] = "box";
        j["min"] = vector_json(b.min);
        j["max"] = vector_json(b.max);
    } else {
        j["type"] = "sphere";
        j["center"] = vector_json(b.center);
        j["radius"] = b.radius;
    }
    j["velocity"] = vector_json(b.velocity);
    if (b.jitter > 0) j["jitter"] = b.jitter;
    return j;
}

json collider_json(const collider& c) {
    json j;
    j["name"] = c.name;
    j["type"] = c.kind == shape::plane ? "plane" : c.kind == shape::sphere ? "sphere" : "box";
    if (c.kind == shape::plane) {
        j["point"] = vector_json(c.center);
        j["normal"] = vector_json(c.normal);
    } else {
        j["inside"] = c.inside;
        j["center"] = vector_json(c.center);
    }
    if (c.kind == shape::box) j["half"] = vector_json(c.half);
    if (c.kind == shape::sphere) j["radius"] = c.radius;
    j["axis"] = vector_json(c.axis);
    j["angle"] = c.angle * degrees_per_radian;  // the file gives degrees
    j["restitution"] = c.restitution;
    j["friction"] = c.friction;
    j["motion"] = {{"velocity", vector_json(c.path.velocity)},
                   {"amplitude", vector_json(c.path.amplitude)},
                   {"frequency", c.path.frequency},
                   {"phase", c.path.phase},
                   {"angular_velocity", c.path.angular_velocity * degrees_per_radian}};
    return j;
}

json section_json(const scene& s, const std::string& section) {
    json j = json::object();
    for (const auto& p : parameters()) {
        if (p.section != section) continue;
        const double v = p.get(s);
        switch (p.kind) {
        case parameter_kind::real: j[p.key] = v; break;
        case parameter_kind::boolean: j[p.key] = v != 0; break;
        case parameter_kind::choice: j[p.key] = p.choices[std::size_t(v)]; break;
        }
    }
    return j;
}

}  // namespace

std::string scene_to_json(const scene& s) {
    json j;
    j["name"] = s.name;
    j["description"] = s.description;
    j["solver"] = to_string(s.solver);
    j["dim"] = s.dim;
    j["particles"] = {{"2d", s.particles_2d}, {"3d", s.particles_3d}};
    j["duration"] = s.duration;
    if (s.steps > 0) j["steps"] = s.steps;
    j["gravity"] = vector_json(s.gravity);
    j["domain"] = {{"min", vector_json(s.domain_min)}, {"max", vector_json(s.domain_max)}};
    if (s.is_periodic()) j["periodic"] = vector_json(s.periodic);
    j["fluid"] = json::array();
    for (const auto& b : s.fluid) j["fluid"].push_back(block_json(b));
    j["colliders"] = json::array();
    for (const auto& c : s.colliders) j["colliders"].push_back(collider_json(c));
    j["viscoelastic"] = section_json(s, "viscoelastic");
    j["sph"] = section_json(s, "sph");
    j["front"] = {{"enabled", s.front.enabled},
                  {"a", s.front.a},
                  {"origin", s.front.origin},
                  {"axis", s.front.axis},
                  {"every_T", s.front.every_T}};
    j["output"] = {{"fps", s.output.fps}, {"every", s.output.every}, {"checkpoint_every", s.output.checkpoint_every}};
    return j.dump(2) + "\n";
}

}  // namespace frnn::sim
