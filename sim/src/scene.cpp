// Scene parsing with error messages that name the key and what was expected, and the lattice
// seeding of fluid blocks.
#include "frnn/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "frnn/error.hpp"
#include "frnn/sim/parameters.hpp"

namespace frnn::sim {

std::string builtin_scene_json(const std::string& name);  // scenes_embedded.cpp (generated)
std::vector<std::string> builtin_scene_list();

namespace {
using json = nlohmann::json;

std::string type_name(const json& j) { return j.type_name(); }

/// One JSON object with its path, for messages; remembers which keys were read so unknown
/// (misspelled) keys are reported.
class reader {
public:
    reader(const json& j, std::string path, const std::string& origin) : j_(j), path_(std::move(path)), origin_(origin) {
        if (!j.is_object()) fail(path_, "expected an object, got " + type_name(j));
    }
    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw error(origin_ + ": key '" + key + "': " + what);
    }
    std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
    bool has(const std::string& k) {
        seen_.insert(k);
        return j_.contains(k);
    }
    const json& at(const std::string& k) { seen_.insert(k); return j_.at(k); }

    double number(const std::string& k, double def, double lo = -1e300, double hi = 1e300) {
        if (!has(k)) return def;
        const json& v = j_.at(k);
        if (!v.is_number()) fail(key(k), "expected a number, got " + type_name(v));
        const double d = v.get<double>();
        if (!std::isfinite(d) || d < lo || d > hi) {
            std::ostringstream m;
            m << "expected a number in [" << lo << ", " << hi << "], got " << d;
            fail(key(k), m.str());
        }
        return d;
    }
    std::int64_t integer(const std::string& k, std::int64_t def, std::int64_t lo, std::int64_t hi) {
        if (!has(k)) return def;
        const json& v = j_.at(k);
        if (!v.is_number_integer()) fail(key(k), "expected an integer, got " + type_name(v) + " " + v.dump());
        const auto i = v.get<std::int64_t>();
        if (i < lo || i > hi)
            fail(key(k), "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(i));
        return i;
    }
    bool boolean(const std::string& k, bool def) {
        if (!has(k)) return def;
        const json& v = j_.at(k);
        if (!v.is_boolean()) fail(key(k), "expected true or false, got " + type_name(v));
        return v.get<bool>();
    }
    std::string string(const std::string& k, const std::string& def) {
        if (!has(k)) return def;
        const json& v = j_.at(k);
        if (!v.is_string()) fail(key(k), "expected a string, got " + type_name(v));
        return v.get<std::string>();
    }
    /// A string among `choices`.
    std::string choice(const std::string& k, const std::string& def, const std::vector<std::string>& choices) {
        const std::string s = string(k, def);
        if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
            std::string list;
            for (const auto& c : choices) list += (list.empty() ? "" : ", ") + ("\"" + c + "\"");
            fail(key(k), "expected one of " + list + ", got \"" + s + "\"");
        }
        return s;
    }
    /// Two or three numbers (a 2D vector gets z = 0).
    vec3 vector(const std::string& k, const vec3& def) {
        if (!has(k)) return def;
        const json& v = j_.at(k);
        if (!v.is_array() || v.size() < 2 || v.size() > 3)
            fail(key(k), "expected an array of 2 or 3 numbers, got " + v.dump());
        vec3 r{0, 0, 0};
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
                fail(key(k) + "[" + std::to_string(i) + "]", "expected a number, got " + v[i].dump());
            r[i] = v[i].get<double>();
        }
        return r;
    }
    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!seen_.count(it.key()) && it.key().rfind("_", 0) != 0)  // "_comment" keys allowed
                fail(key(it.key()), "unknown key (misspelled?)");
    }
    const std::string& path() const { return path_; }
    const std::string& origin() const { return origin_; }

private:
    const json& j_;
    std::string path_;
    const std::string& origin_;
    std::set<std::string> seen_;
};

motion read_motion(reader& r) {
    motion m;
    m.velocity = r.vector("velocity", m.velocity);
    m.amplitude = r.vector("amplitude", m.amplitude);
    m.frequency = r.number("frequency", 0, 0);
    m.phase = r.number("phase", 0);
    m.angular_velocity = r.number("angular_velocity", 0);
    r.finish();
    return m;
}

collider read_collider(reader& r) {
    collider c;
    const std::string type = r.choice("type", "", collider_types());
    c.name = r.string("name", type);
    c.kind = shape(std::find(collider_types().begin(), collider_types().end(), type) - collider_types().begin());
    c.inside = r.boolean("inside", false);
    if (c.inside && c.kind == shape::plane) r.fail(r.key("inside"), "a plane has no inside; use its normal");
    c.center = r.vector(c.kind == shape::plane ? "point" : "center", c.center);
    if (c.kind == shape::plane) {
        c.normal = r.vector("normal", c.normal);
        if (c.normal[0] == 0 && c.normal[1] == 0 && c.normal[2] == 0) r.fail(r.key("normal"), "expected a non-zero vector");
    }
    if (c.kind == shape::box) {
        c.half = r.vector("half", c.half);
        for (double h : c.half)
            if (h <= 0) r.fail(r.key("half"), "expected positive half extents");
    }
    if (c.kind == shape::sphere) c.radius = r.number("radius", c.radius, 1e-9);
    c.axis = r.vector("axis", c.axis);
    c.angle = r.number("angle", 0) * 3.14159265358979323846 / 180;
    c.restitution = r.number("restitution", 0, 0, 1);
    c.friction = r.number("friction", 0, 0, 10);
    if (r.has("motion")) {
        reader m(r.at("motion"), r.key("motion"), r.origin());
        c.path = read_motion(m);
        c.path.angular_velocity *= 3.14159265358979323846 / 180;
    }
    r.finish();
    return c;
}

fluid_block read_block(reader& r) {
    fluid_block b;
    const std::string type = r.choice("type", "box", fluid_block_types());
    b.kind = fluid_block::kind_t(std::find(fluid_block_types().begin(), fluid_block_types().end(), type) - fluid_block_types().begin());
    if (b.kind == fluid_block::kind_t::box) {
        b.min = r.vector("min", b.min);
        b.max = r.vector("max", b.max);
        for (int a = 0; a < 2; ++a)
            if (b.max[a] <= b.min[a]) r.fail(r.key("max"), "expected max > min on every axis");
    } else {
        b.center = r.vector("center", b.center);
        b.radius = r.number("radius", b.radius, 1e-9);
    }
    b.velocity = r.vector("velocity", b.velocity);
    b.jitter = r.number("jitter", b.jitter, 0, 0.5);
    r.finish();
    return b;
}

/// The keys of a solver section, through the parameter table (so a new row is parsed too).
void read_parameters(reader& r, const std::string& section, scene& s) {
    for (const auto& p : parameters()) {
        if (p.section != section) continue;
        switch (p.kind) {
        case parameter_kind::real: p.set(s, r.number(p.key, p.get(s), p.min, p.max)); break;
        case parameter_kind::boolean: p.set(s, r.boolean(p.key, p.get(s) != 0) ? 1 : 0); break;
        case parameter_kind::choice: {
            const std::string name = r.choice(p.key, p.choices[std::size_t(p.get(s))], p.choices);
            p.set(s, double(std::find(p.choices.begin(), p.choices.end(), name) - p.choices.begin()));
            break;
        }
        }
    }
    r.finish();
}

}  // namespace

std::string to_string(solver_kind k) { return solver_names()[std::size_t(k)]; }

const std::vector<std::string>& solver_names() {
    static const std::vector<std::string> names{"viscoelastic", "sph"};
    return names;
}
const std::vector<std::string>& fluid_block_types() {
    static const std::vector<std::string> names{"box", "sphere"};
    return names;
}
const std::vector<std::string>& collider_types() {
    static const std::vector<std::string> names{"plane", "sphere", "box"};
    return names;
}

scene parse_scene(const std::string& text, const std::string& origin) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {  // a syntax error, or a number beyond double (out_of_range)
        throw error(origin + ": not valid JSON: " + e.what());
    }
    reader r(j, "", origin);
    scene s;
    s.name = r.string("name", "scene");
    s.description = r.string("description", "");
    const std::string solver = r.choice("solver", "viscoelastic", solver_names());
    s.solver = solver_kind(std::find(solver_names().begin(), solver_names().end(), solver) - solver_names().begin());
    s.dim = int(r.integer("dim", 3, 2, 3));
    if (r.has("particles")) {
        const json& p = r.at("particles");
        if (p.is_number_integer()) {
            s.particles_2d = s.particles_3d = std::size_t(r.integer("particles", 1, 1, 1 << 28));
        } else {
            reader pr(p, "particles", origin);
            s.particles_2d = std::size_t(pr.integer("2d", std::int64_t(s.particles_2d), 1, 1 << 28));
            s.particles_3d = std::size_t(pr.integer("3d", std::int64_t(s.particles_3d), 1, 1 << 28));
            pr.finish();
        }
    }
    s.duration = r.number("duration", s.duration, 0);
    s.steps = std::uint64_t(r.integer("steps", 0, 0, std::int64_t(1) << 40));
    s.gravity = r.vector("gravity", s.gravity);
    if (!r.has("domain")) r.fail("domain", "missing: expected {\"min\": [x, y, z], \"max\": [x, y, z]}");
    {
        reader d(r.at("domain"), "domain", origin);
        s.domain_min = d.vector("min", s.domain_min);
        s.domain_max = d.vector("max", s.domain_max);
        for (int a = 0; a < 3; ++a)
            if (s.domain_max[a] <= s.domain_min[a]) d.fail("domain.max", "expected max > min on every axis");
        d.finish();
    }
    s.periodic = r.vector("periodic", s.periodic);
    for (int a = 0; a < 3; ++a)
        if (s.periodic[a] < 0) r.fail("periodic", "expected box lengths >= 0 (0: open), got " + j.at("periodic").dump());
    if (!r.has("fluid") || !j.at("fluid").is_array() || j.at("fluid").empty())
        r.fail("fluid", "expected a non-empty array of fluid blocks");
    for (std::size_t i = 0; i < j.at("fluid").size(); ++i) {
        reader b(j.at("fluid")[i], "fluid[" + std::to_string(i) + "]", origin);
        s.fluid.push_back(read_block(b));
    }
    if (r.has("colliders")) {
        if (!j.at("colliders").is_array()) r.fail("colliders", "expected an array, got " + type_name(j.at("colliders")));
        for (std::size_t i = 0; i < j.at("colliders").size(); ++i) {
            reader c(j.at("colliders")[i], "colliders[" + std::to_string(i) + "]", origin);
            s.colliders.push_back(read_collider(c));
        }
    }
    for (const char* section : {"viscoelastic", "sph"})
        if (r.has(section)) {
            reader v(r.at(section), section, origin);
            read_parameters(v, section, s);
        }
    if (r.has("front")) {
        reader f(r.at("front"), "front", origin);
        s.front.enabled = f.boolean("enabled", true);
        s.front.a = f.number("a", s.front.a, 1e-9);
        s.front.origin = f.number("origin", s.front.origin);
        s.front.axis = int(f.integer("axis", 0, 0, 2));
        s.front.every_T = f.number("every_T", s.front.every_T, 1e-6);
        f.finish();
    }
    if (r.has("output")) {
        reader o(r.at("output"), "output", origin);
        s.output.fps = o.number("fps", s.output.fps, 1e-6);
        s.output.every = int(o.integer("every", 0, 0, 1 << 30));
        s.output.checkpoint_every = int(o.integer("checkpoint_every", s.output.checkpoint_every, 1, 1 << 30));
        o.finish();
    }
    r.finish();
    if (s.dim == 2) apply(s, {});  // a 2D scene's colliders live in the xy plane
    return s;
}

scene load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw error("cannot open scene file '" + path + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_scene(ss.str(), path);
}

std::vector<std::string> builtin_scene_names() { return builtin_scene_list(); }

std::string builtin_scene_text(const std::string& name) {
    std::string t = builtin_scene_json(name);
    if (t.empty()) {
        std::string list;
        for (const auto& n : builtin_scene_list()) list += (list.empty() ? "" : ", ") + n;
        throw error("unknown scene '" + name + "' (shipped scenes: " + list + ")");
    }
    return t;
}

scene builtin_scene(const std::string& name) { return parse_scene(builtin_scene_text(name), "scene " + name); }

void apply(scene& s, const scene_overrides& o) {
    if (o.solver) s.solver = *o.solver;
    if (o.dim) s.dim = *o.dim;
    if (o.particles) s.particles_2d = s.particles_3d = *o.particles;
    if (o.steps) s.steps = *o.steps;
    if (o.duration) s.duration = *o.duration, s.steps = 0;
    if (o.every) s.output.every = *o.every;
    if (s.dim == 2) {
        for (auto& c : s.colliders) flatten_to_2d(c);
        s.gravity[2] = 0;
        s.periodic[2] = 0;
        for (auto& b : s.fluid) b.velocity[2] = 0, b.center[2] = 0;
    }
}

namespace {
/// A number in [0, 1) from the indices alone (splitmix64's finaliser over each in turn): the
/// same jitter in every run, on every rank and at every thread count.
double unit_hash(std::initializer_list<std::uint64_t> indices) {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (const std::uint64_t v : indices) {
        h += v + 0x9e3779b97f4a7c15ULL;
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
        h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
        h ^= h >> 31;
    }
    return double(h >> 11) * 0x1.0p-53;
}
}  // namespace

seeded_particles seed(const scene& s) {
    const int dim = s.dim;
    auto inside = [&](const fluid_block& b, const vec3& p) {
        if (b.kind == fluid_block::kind_t::box) {
            for (int a = 0; a < dim; ++a)
                if (p[a] < b.min[a] || p[a] > b.max[a]) return false;
            return true;
        }
        double d2 = 0;
        for (int a = 0; a < dim; ++a) d2 += (p[a] - b.center[a]) * (p[a] - b.center[a]);
        return d2 <= b.radius * b.radius;
    };
    double volume = 0;
    for (std::size_t k = 0; k < s.fluid.size(); ++k) {
        const auto& b = s.fluid[k];
        double v = 1;
        if (b.kind == fluid_block::kind_t::box) {
            for (int a = 0; a < dim; ++a) {
                // The parser checks x and y; z counts once the dimension is known.
                if (!(b.max[a] > b.min[a]))
                    throw error("fluid[" + std::to_string(k) + "]: a box needs max > min on every axis (axis " +
                                std::to_string(a) + ")");
                v *= b.max[a] - b.min[a];
            }
        } else {
            v = dim == 2 ? 3.14159265358979 * b.radius * b.radius : 4.18879020478639 * std::pow(b.radius, 3);
        }
        volume += v;
    }
    const double spacing = std::pow(volume / double(s.target_particles()), 1.0 / dim);
    if (!std::isfinite(spacing) || !(spacing > 0))
        throw error("the fluid's volume " + std::to_string(volume) + " over " + std::to_string(s.target_particles()) +
                    " particles gives no particle spacing");
    seeded_particles out;
    out.spacing = spacing;
    // The lattice points visited, bounded before any is: a block far thinner than the spacing on
    // one axis and far wider on another would otherwise take more points than memory holds.
    const double most = 8.0 * double(s.target_particles()) + double(1 << 20);
    double visited = 0;
    for (std::size_t k = 0; k < s.fluid.size(); ++k) {
        const auto& b = s.fluid[k];
        double points = 1;
        for (int a = 0; a < dim; ++a) {
            const double width = b.kind == fluid_block::kind_t::box ? b.max[a] - b.min[a] : 2 * b.radius;
            points *= std::max(1.0, std::round(width / spacing));
        }
        visited += points;
        if (!(visited <= most))
            throw error("fluid[" + std::to_string(k) + "]: the blocks' lattices at spacing " + std::to_string(spacing) +
                        " hold " + std::to_string(visited) + " points, more than " + std::to_string(std::llround(most)) +
                        " (8 per particle, plus 2^20): a block much thinner than the spacing on some axis");
    }
    for (std::size_t block = 0; block < s.fluid.size(); ++block) {
        const auto& b = s.fluid[block];
        vec3 lo, hi;
        std::array<std::int64_t, 3> n{1, 1, 1};
        for (int a = 0; a < dim; ++a) {
            lo[a] = b.kind == fluid_block::kind_t::box ? b.min[a] : b.center[a] - b.radius;
            hi[a] = b.kind == fluid_block::kind_t::box ? b.max[a] : b.center[a] + b.radius;
            n[a] = std::max<std::int64_t>(1, std::llround((hi[a] - lo[a]) / spacing));
        }
        // Cell-centred lattice: a box of width L holds round(L / spacing) particles per axis.
        for (std::int64_t k = 0; k < n[2]; ++k)
            for (std::int64_t j = 0; j < n[1]; ++j)
                for (std::int64_t i = 0; i < n[0]; ++i) {
                    const std::int64_t idx[3] = {i, j, k};
                    vec3 p{0, 0, 0};
                    for (int a = 0; a < dim; ++a) {
                        const double step = b.kind == fluid_block::kind_t::box ? (hi[a] - lo[a]) / double(n[a]) : spacing;
                        p[a] = lo[a] + (double(idx[a]) + 0.5) * step;
                    }
                    if (!inside(b, p)) continue;
                    for (int a = 0; a < dim; ++a) {
                        if (b.jitter > 0) {
                            const double step = b.kind == fluid_block::kind_t::box ? (hi[a] - lo[a]) / double(n[a]) : spacing;
                            p[a] += b.jitter * step * (2 * unit_hash({block, std::uint64_t(i), std::uint64_t(j), std::uint64_t(k), std::uint64_t(a)}) - 1);
                        }
                        out.x.push_back(float(p[a]));
                        out.v.push_back(float(b.velocity[a]));
                    }
                }
    }
    out.count = out.x.size() / std::size_t(dim);
    if (out.count == 0) throw error("scene '" + s.name + "': its fluid blocks hold no particle");
    return out;
}

}  // namespace frnn::sim
