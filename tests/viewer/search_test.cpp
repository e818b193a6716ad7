// The search made visible: a click at a particle's pixel picks it; the neighbors highlighted are
// exactly those within r (brute force over the dumped positions); the cells outlined are exactly
// the cells whose box lies within r of it, and the cell grid toggle outlines the block of cells
// the search visits, both recomputed here from the dumped grid geometry.
#include <gtest/gtest.h>

#include <set>

#include "projection.hpp"
#include "viewer_run.hpp"

using namespace frnn::test;

namespace {
const char* block_scene = R"({"name": "block", "dim": %d, "particles": %d, "gravity": [0, 0, 0],
  "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
  "fluid": [{"type": "box", "min": [0.2, 0.2, 0.2], "max": [0.8, 0.8, 0.8]}]})";

using cell = std::array<long long, 3>;

/// One step, paused, then the actions of `camera` and `more` (JSON objects, either may be empty).
nlohmann::json run(const scratch_dir& dir, int dim, int particles, const std::string& camera, const std::string& more) {
    char text[512];
    std::snprintf(text, sizeof text, block_scene, dim, particles);
    write_text(dir / "block.json", text);
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 0, "do": "pause"}, {"frame": 0, "do": "step"})" +
                                        (camera.empty() ? "" : ", " + camera) + (more.empty() ? "" : ", " + more) + "]}");
    const auto r = run_viewer(dir, "block.json --script script.json --frames 5 --state state.json");
    EXPECT_EQ(r.code, 0) << r.err;
    return read_json(dir / "state.json");
}

std::string click(const pixel_xy& at) {
    return R"({"frame": 2, "do": "click", "x": )" + std::to_string(at.x) + R"(, "y": )" + std::to_string(at.y) + "}";
}

std::array<double, 3> position(const nlohmann::json& state, std::size_t k) {
    const auto& x = state.at("x");
    return {x[k * 3], x[k * 3 + 1], x[k * 3 + 2]};
}

/// The particle nearest the middle of the block: one with neighbors on every side.
std::size_t middle_particle(const nlohmann::json& state) {
    std::size_t best = 0;
    double best_d = 1e9;
    for (std::size_t k = 0; k < state.at("particles").get<std::size_t>(); ++k) {
        const auto p = position(state, k);
        const double d = std::hypot(p[0] - 0.5, p[1] - 0.5, state.at("dim") == 2 ? 0.0 : p[2] - 0.5);
        if (d < best_d) best_d = d, best = k;
    }
    return best;
}

std::vector<std::size_t> brute_force_neighbors(const nlohmann::json& state, std::size_t k) {
    const double r = state.at("search").at("radius");
    const auto p = position(state, k);
    std::vector<std::size_t> out;
    for (std::size_t j = 0; j < state.at("particles").get<std::size_t>(); ++j) {
        const auto q = position(state, j);
        double d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += (q[a] - p[a]) * (q[a] - p[a]);
        if (j != k && std::sqrt(d2) <= r) out.push_back(j);
    }
    return out;
}

struct grid_geometry {
    std::array<double, 3> origin, edge;  // lower corner of cell (0, 0, 0), cell edges
    std::array<long long, 3> dims;
    double scale;
    int reach;
    explicit grid_geometry(const nlohmann::json& g)
        : origin(g.at("origin")), edge(g.at("cell")), dims(g.at("dims")), scale(g.at("scale")), reach(g.at("reach")) {}
    double lower(const cell& c, int a) const { return (origin[a] + double(c[a]) * edge[a]) / scale; }
    double upper(const cell& c, int a) const { return (origin[a] + double(c[a] + 1) * edge[a]) / scale; }
};

/// Every cell of the grid whose box lies within r of p (over the scene's axes).
std::set<cell> cells_within_radius(const nlohmann::json& state, const std::array<double, 3>& p) {
    const grid_geometry g(state.at("search").at("grid"));
    const double r = state.at("search").at("radius");
    const int dim = state.at("dim");
    std::set<cell> out;
    for (long long z = 0; z < g.dims[2]; ++z)
        for (long long y = 0; y < g.dims[1]; ++y)
            for (long long x = 0; x < g.dims[0]; ++x) {
                const cell c{x, y, z};
                double d2 = 0;
                for (int a = 0; a < dim; ++a) {
                    const double gap = std::max({g.lower(c, a) - p[a], 0.0, p[a] - g.upper(c, a)});
                    d2 += gap * gap;
                }
                if (std::sqrt(d2) <= r) out.insert(c);
            }
    return out;
}

std::set<cell> as_set(const nlohmann::json& cells) {
    std::set<cell> out;
    for (const auto& c : cells) out.insert(cell(c));
    return out;
}
}  // namespace

/// The neighbors and the searched cells of the dumped search are those recomputed here.
void expect_search_of(const nlohmann::json& state, std::size_t k) {
    const auto& search = state.at("search");
    const auto expected = brute_force_neighbors(state, k);
    EXPECT_GE(expected.size(), 3u);
    EXPECT_EQ(search.at("neighbors").get<std::vector<std::size_t>>(), expected);
    const auto cells = as_set(search.at("cells"));
    EXPECT_EQ(cells.size(), search.at("cells").size());  // each once
    EXPECT_EQ(cells, cells_within_radius(state, position(state, k)));
}

TEST(ViewerSearch, PickedParticleShowsItsNeighborsAndTheCellsSearched) {
    const scratch_dir dir("viewer_search");
    const std::array<double, 3> target{0.5, 0.5, 0.5};
    const std::string camera = R"({"frame": 0, "do": "camera", "target": [0.5, 0.5, 0.5], "distance": 1.6, "yaw": 30, "pitch": 25, "fov": 40})";
    const auto look = run(dir, 3, 1000, camera, "");
    EXPECT_TRUE(look.at("picked").is_null());
    EXPECT_TRUE(look.at("search").at("neighbors").empty());
    EXPECT_TRUE(look.at("search").at("cells").empty());
    // The particle nearest the eye: the ray through its center enters no other sphere first.
    const auto eye = orbit_eye(target, 1.6, 30, 25);
    std::size_t front = 0;
    double nearest = 1e9;
    for (std::size_t j = 0; j < look.at("particles").get<std::size_t>(); ++j) {
        const auto q = position(look, j);
        const double d = std::hypot(q[0] - eye[0], q[1] - eye[1], q[2] - eye[2]);
        if (d < nearest) nearest = d, front = j;
    }
    const std::array<int, 4> vp = look.at("camera").at("viewport");
    const auto at = project(position(look, front), eye, target, 40, vp, look.at("camera").at("height"));
    const auto after = run(dir, 3, 1000, camera, click(at));
    ASSERT_EQ(after.at("picked"), front);
    expect_search_of(after, front);
    EXPECT_FALSE(after.at("search").at("cell_grid").get<bool>());
    EXPECT_TRUE(after.at("search").at("grid_cells").empty());
}

TEST(ViewerSearch, CellGridToggleOutlinesTheBlockTheSearchVisits) {
    const scratch_dir dir("viewer_search_2d");
    const auto look = run(dir, 2, 400, "", R"({"frame": 1, "do": "pause"})");
    const std::size_t k = middle_particle(look);
    const auto& cam = look.at("camera");
    const std::array<int, 4> vp = cam.at("viewport");
    const std::array<double, 3> target = cam.at("target");
    const double scale = vp[3] / (2 * cam.at("half_height").get<double>());
    const int height = cam.at("height");
    const auto p = position(look, k);
    const pixel_xy at{vp[0] + 0.5 * vp[2] + (p[0] - target[0]) * scale, height - (vp[1] + 0.5 * vp[3] + (p[1] - target[1]) * scale)};
    const auto after = run(dir, 2, 400, "", click(at) + R"(, {"frame": 3, "do": "key", "key": "g"})");
    ASSERT_EQ(after.at("picked"), k);
    expect_search_of(after, k);
    const auto& search = after.at("search");
    EXPECT_TRUE(search.at("cell_grid").get<bool>());
    // The block: reach cells on each side of the particle's cell, within the grid.
    const grid_geometry g(search.at("grid"));
    std::array<long long, 2> first{}, last{};
    for (int a = 0; a < 2; ++a) {
        const long long c = std::clamp((long long)std::floor((p[a] * g.scale - g.origin[a]) / g.edge[a]), 0LL, g.dims[a] - 1);
        first[a] = std::max(c - g.reach, 0LL), last[a] = std::min(c + g.reach, g.dims[a] - 1);
    }
    std::set<cell> block;
    for (long long y = first[1]; y <= last[1]; ++y)
        for (long long x = first[0]; x <= last[0]; ++x) block.insert({x, y, 0});
    EXPECT_EQ(as_set(search.at("grid_cells")), block);
    EXPECT_EQ(block.size(), 9u);  // the middle of the block is far from the grid's border
    const auto searched = as_set(search.at("cells"));
    EXPECT_TRUE(std::includes(block.begin(), block.end(), searched.begin(), searched.end()));
}
