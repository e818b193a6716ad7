// The memory of a query: at most its output plus query_bytes_per_point * N bytes (and a fixed
// allowance for the allocator), also for huge radii and far outliers. Each case runs in a
// child process under an address-space limit of exactly that much above what it holds before
// the query; a query that needed more would fail to allocate. The sanitizer tree skips these
// (its shadow memory takes terabytes of address space).
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <limits>

#include "frnn/grid.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool sanitized = true;
#else
constexpr bool sanitized = false;
#endif

/// The bound this test holds the library to (docs/DESIGN.md states it).
constexpr std::size_t query_bytes_per_point = 64;
/// Allocator and page granularity, the stack, the runtime's own small allocations.
constexpr std::size_t fixed_allowance = std::size_t(16) << 20;

std::size_t address_space_bytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long pages = 0;
    const int got = std::fscanf(f, "%lu", &pages);
    std::fclose(f);
    return got == 1 ? std::size_t(pages) * std::size_t(sysconf(_SC_PAGESIZE)) : 0;
}

/// Runs `query` in a child process whose address space may grow by `allowed` bytes; true when
/// it completed without running out of memory.
bool completes_within(std::size_t allowed, const std::function<void()>& prepare, const std::function<void()>& query) {
    const pid_t pid = fork();
    if (pid == 0) {
        int code = 0;
        try {
            prepare();
            const std::size_t limit = address_space_bytes() + allowed;
            rlimit rl{limit, limit};
            if (setrlimit(RLIMIT_AS, &rl) != 0) _exit(3);
            query();
        } catch (const std::bad_alloc&) {
            code = 1;
        } catch (...) {
            code = 2;
        }
        _exit(code);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Full lists with distances over `pts` (`entries` in all): within the bound and, when `bites`
/// (outputs far larger than the free memory the process already holds), not within half the
/// output, which shows that the limit does hold the query.
template <class T, int D>
void lists_within_bound(const std::vector<T>& pts, T r, grid_kind kind, std::size_t entries, const char* what,
                        bool bites = true) {
    SCOPED_TRACE(what);
    const std::size_t n = pts.size() / D;
    const std::size_t output = (n + 1) * 8 + entries * (4 + sizeof(T));
    grid<T, D> g;
    grid_options opt;
    opt.kind = kind;
    opt.threads = 1;
    auto prepare = [&] { g.build(pts, r, opt); };
    std::size_t got = 0;
    auto query = [&] {
        list_options o;
        o.distances = true;
        got = g.neighbor_lists(o).size();
        if (got != entries) _exit(4);
        (void)g.count_neighbors();
        (void)g.query_counts(std::span<const T>(pts).first(D * 100));
    };
    EXPECT_TRUE(completes_within(output + query_bytes_per_point * n + fixed_allowance, prepare, query));
    if (bites) {
        EXPECT_FALSE(completes_within(output / 2, prepare, query)) << "the limit does not bite";
    }
}

// A rebuild that runs out of memory leaves an empty grid that answers every query.
TEST(OracleMemory, FailedAllocationLeavesAnEmptyGrid) {
    if (sanitized) GTEST_SKIP() << "address space of the sanitizer";
    grid<float, 3> g;
    const auto small = uniform_points<float, 3>(1000, 0, 10, 4);
    const auto large = uniform_points<float, 3>(4000000, 0, 150, 5);  // about 100 MB of structure
    auto prepare = [&] { g.build(small, 1.0f); };
    auto query = [&] {
        grid_options o;
        o.threads = 1;
        try {
            g.build(large, 1.0f, o);
        } catch (const std::bad_alloc&) {
            if (g.size() != 0 || !g.count_neighbors().empty() || g.neighbor_lists().rows() != 0) _exit(5);
            if (g.query_counts(small) != std::vector<std::uint32_t>(1000, 0)) _exit(6);
            g.rebuild(small);  // and it builds again
            if (g.size() != 1000 || g.neighbor_lists().size() == 0) _exit(7);
            return;
        }
        _exit(8);  // the limit did not bite
    };
    EXPECT_TRUE(completes_within(std::size_t(20) << 20, prepare, query));
}

TEST(OracleMemory, HugeRadiusAndFarOutliers) {
    if (sanitized) GTEST_SKIP() << "address space of the sanitizer";
    const std::size_t n = 3000;
    const auto pts = uniform_points<double, 3>(n, -10, 10, 1);
    for (auto kind : {grid_kind::automatic, grid_kind::hashed})
        lists_within_bound<double, 3>(pts, 1e200, kind, n * (n - 1), "radius 1e200");
    const auto pf = uniform_points<float, 3>(n, -10, 10, 2);
    lists_within_bound<float, 3>(pf, 1e20f, grid_kind::automatic, n * (n - 1), "float radius 1e20");
    lists_within_bound<float, 3>(pf, std::numeric_limits<float>::max(), grid_kind::uniform, n * (n - 1),
                                 "float radius FLT_MAX");

    // A bulk of 200,000 points with two far outliers: at the ends of the float range (auto
    // folds them into a uniform grid), at +-1e12 for the hashed grid (within its keys).
    for (auto [kind, far] : {std::pair{grid_kind::automatic, 3e38}, std::pair{grid_kind::hashed, 1e12}}) {
        auto bulk = uniform_points<float, 3>(200000, 0, 60, 3);
        append_point<float, 3>(bulk, far);
        append_point<float, 3>(bulk, -far);
        grid<float, 3> g(bulk, 1.0f);
        lists_within_bound<float, 3>(bulk, 1.0f, kind, g.neighbor_lists().size(), "far outliers", false);
    }
}

}  // namespace
}  // namespace frnn::test
