// A build or rebuild that throws on invalid input leaves the grid exactly as it was: same
// configuration, same structure, same answers (compared with the oracle after every failure).
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

/// What a failed build must not change.
template <class T, int D>
struct snapshot {
    std::size_t size, cells;
    grid_kind kind;
    T radius, scale;
    int reach;
    bool periodic;
    std::vector<double> box;
    std::vector<std::uint32_t> perm;

    explicit snapshot(const grid<T, D>& g)
        : size(g.size()), cells(g.slot_count()), kind(g.kind()), radius(g.radius()), scale(g.search_scale()),
          reach(g.reach()), periodic(g.periodic()), box(g.options().periodic),
          perm(g.sorted_to_original().begin(), g.sorted_to_original().end()) {}
    bool operator==(const snapshot&) const = default;
};

template <class T, int D>
void failures_leave_grid(const std::vector<T>& pts, T r, const grid_options& opt, const std::string& what) {
    SCOPED_TRACE(what);
    grid<T, D> g(pts, r, opt);
    const snapshot<T, D> before(g);
    const auto queries = query_points<T, D>(pts, double(r), 20, opt.periodic, 5);

    auto bad_coords = pts;
    bad_coords[7 * D + 1] = std::numeric_limits<T>::quiet_NaN();
    std::vector<T> ragged(pts.begin(), pts.end() - 1);
    const T nan = std::numeric_limits<T>::quiet_NaN();
    std::vector<std::pair<std::string, std::function<void()>>> failures = {
        {"rebuild with a NaN coordinate", [&] { g.rebuild(bad_coords); }},
        {"rebuild with a ragged array", [&] { g.rebuild(ragged); }},
        {"build with radius 0", [&] { g.build(pts, T(0), opt); }},
        {"build with radius NaN", [&] { g.build(pts, nan, opt); }},
        {"build with radius -1", [&] { g.build(pts, T(-1), opt); }},
        {"build with an infinite coordinate", [&] {
             auto p = pts;
             p[3] = std::numeric_limits<T>::infinity();
             g.build(p, r, opt);
         }},
    };
    auto with = [&](std::string name, auto change) {
        grid_options o = opt;
        change(o);
        failures.emplace_back(name, [&g, &pts, r, o] { g.build(pts, r, o); });
    };
    with("cell size 2r", [&](grid_options& o) { o.cell_size = 2 * double(r); });
    with("cell size r/5", [&](grid_options& o) { o.cell_size = double(r) / 5; });
    with("a box smaller than 2r", [&](grid_options& o) { o.periodic.assign(D, 1.5 * double(r)); });
    with("a box of wrong size", [&](grid_options& o) { o.periodic.assign(D + 1, 100.0); });
    with("a box of NaN", [&](grid_options& o) { o.periodic.assign(D, std::numeric_limits<double>::quiet_NaN()); });
    with("half a domain", [&](grid_options& o) { o.periodic.clear(), o.domain_min.assign(D, 0.0); });
    with("a reversed domain", [&](grid_options& o) {
        o.periodic.clear(), o.domain_min.assign(D, 5.0), o.domain_max.assign(D, 0.0);
    });

    for (const auto& [name, fail] : failures) {
        SCOPED_TRACE(name);
        bool threw = false;
        try {
            fail();
        } catch (const frnn::error&) {
            threw = true;
        }
        EXPECT_TRUE(threw);
        EXPECT_TRUE((snapshot<T, D>(g) == before)) << "the grid changed";
        check_grid<T, D>(g, pts, r, opt.periodic, queries, depth::basic);
    }
}

TEST(OracleFailedBuild, LeavesGridAsItWas) {
    for (auto kind : {grid_kind::automatic, grid_kind::uniform, grid_kind::hashed}) {
        grid_options opt;
        opt.kind = kind;
        opt.threads = 1;
        failures_leave_grid<double, 3>(uniform_points<double, 3>(400, 0, 8, 1), 1.0, opt, "double 3D " + kind_name(kind));
        failures_leave_grid<float, 2>(uniform_points<float, 2>(400, -5, 5, 2), 0.6f, opt, "float 2D " + kind_name(kind));
    }
    grid_options periodic;
    periodic.periodic = {8, 9, 10};
    periodic.threads = 1;
    failures_leave_grid<double, 3>(uniform_points<double, 3>(400, 0, 8, 3), 1.0, periodic, "periodic");
    grid_options scaled;
    scaled.threads = 1;
    failures_leave_grid<float, 3>(uniform_points<float, 3>(200, -1e30, 1e30, 4), 3e29f, scaled, "scaled search");
}

// The radius too small for the coordinates' range (beyond any grid) is refused clearly.
TEST(OracleFailedBuild, RadiusTooSmallForTheRange) {
    const std::vector<float> pts = {0, 0, 1e-40f, 0, 3e38f, 0};
    try {
        grid<float, 2> g(pts, 1e-44f);
        ADD_FAILURE() << "no error";
    } catch (const frnn::error& e) {
        EXPECT_NE(std::string(e.what()).find("too small"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace frnn::test
