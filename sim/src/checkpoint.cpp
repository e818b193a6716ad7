// Reading and writing checkpoint.bin (format in checkpoint.hpp).
#include "checkpoint.hpp"

#include <nlohmann/json.hpp>
#include <sstream>

#include "frnn/io/atomic_file.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"
#include "particle_solver.hpp"

namespace frnn::sim::detail {
namespace {
using json = nlohmann::json;

// Format 2 adds the wall particles' state (density, pressure term) after the WCSPH arrays.
constexpr char magic[8] = {'F', 'R', 'N', 'N', 'S', 'I', 'M', '2'};
constexpr char magic_1[8] = {'F', 'R', 'N', 'N', 'S', 'I', 'M', '1'};

json overrides_to_json(const scene_overrides& o) {
    json j = json::object();
    if (o.solver) j["solver"] = to_string(*o.solver);
    if (o.dim) j["dim"] = *o.dim;
    if (o.particles) j["particles"] = *o.particles;
    if (o.steps) j["steps"] = *o.steps;
    if (o.duration) j["duration"] = *o.duration;
    if (o.every) j["every"] = *o.every;
    return j;
}
scene_overrides overrides_from_json(const json& j) {
    scene_overrides o;
    if (j.contains("solver")) o.solver = j["solver"] == "sph" ? solver_kind::sph : solver_kind::viscoelastic;
    if (j.contains("dim")) o.dim = j["dim"].get<int>();
    if (j.contains("particles")) o.particles = j["particles"].get<std::size_t>();
    if (j.contains("steps")) o.steps = j["steps"].get<std::uint64_t>();
    if (j.contains("duration")) o.duration = j["duration"].get<double>();
    if (j.contains("every")) o.every = j["every"].get<int>();
    return o;
}

void write_string(std::ostream& o, const std::string& s) {
    write_pod(o, std::uint64_t(s.size()));
    o.write(s.data(), std::streamsize(s.size()));
}
std::string read_string(std::istream& in) {
    std::uint64_t n = 0;
    read_pod(in, n);
    if (n > bytes_left(in)) throw error("checkpoint: truncated (a string of " + std::to_string(n) + " bytes)");
    std::string s(n, '\0');
    in.read(s.data(), std::streamsize(n));
    if (!in) throw error("checkpoint: truncated");
    return s;
}

}  // namespace

void write_checkpoint(const std::string& path, const checkpoint_header& h, const solver& sol) {
    std::ostringstream o(std::ios::binary);
    o.write(magic, 8);
    write_string(o, h.scene_json);
    write_string(o, h.origin);
    json meta;
    meta["overrides"] = overrides_to_json(h.ov);
    meta["frames"] = h.frames;
    meta["front"] = h.front;
    write_string(o, meta.dump());
    write_pod(o, h.next_frame_time);
    write_pod(o, h.next_front_T);
    sol.save(o);
    io::write_file_atomically(path, o.str());
}

checkpoint_header read_checkpoint_header(std::istream& in, const std::string& name) {
    char m[8] = {};
    in.read(m, 8);
    if (in && std::string(m, 8) == std::string(magic_1, 8))
        throw error(name + " was written by an older frnn (checkpoint format 1, without the wall particles' state): "
                           "run the scene again");
    if (!in || std::string(m, 8) != std::string(magic, 8)) throw error(name + " is not a frnn sim checkpoint");
    checkpoint_header h;
    h.scene_json = read_string(in);
    h.origin = read_string(in);
    try {
        const json meta = json::parse(read_string(in));
        h.ov = overrides_from_json(meta.at("overrides"));
        h.frames = meta.at("frames").get<std::vector<std::pair<double, std::string>>>();
        h.front = meta.at("front").get<std::vector<std::pair<double, double>>>();
    } catch (const json::exception& e) {
        throw error(name + ": corrupt metadata: " + e.what());
    }
    read_pod(in, h.next_frame_time);
    read_pod(in, h.next_front_T);
    return h;
}

}  // namespace frnn::sim::detail
