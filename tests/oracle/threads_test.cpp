// Thread-count invariance: builds and bulk queries at 1, 2 and 4 threads give bit-identical
// permutations and csr arrays (offsets, indices, distances), including the traversal order
// row_order::none. The oracle tests cover correctness; these cover determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "oracle/oracle_check.hpp"
#include "oracle/point_sets.hpp"

namespace frnn::test {
namespace {

template <class U, class A, class B>
bool same_bits(const std::vector<U, A>& a, const std::vector<U, B>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(U)) == 0);
}

template <class T>
std::string csr_diff(const csr<T>& a, const csr<T>& b) {
    if (!same_bits(a.offsets, b.offsets)) return "offsets differ";
    if (!same_bits(a.indices, b.indices)) return "indices differ";
    if (!same_bits(a.distances, b.distances)) return "distances differ";
    return {};
}

/// Everything a grid outputs, for one thread count.
template <class T>
struct outputs {
    grid_kind kind;
    std::vector<std::uint32_t> perm, inverse, counts, counts_sorted, query_counts;
    std::vector<csr<T>> lists;
};

template <class T, int D>
outputs<T> collect(const grid<T, D>& g, const std::vector<T>& queries) {
    outputs<T> o;
    o.kind = g.kind();
    o.perm.assign(g.sorted_to_original().begin(), g.sorted_to_original().end());
    o.inverse.assign(g.original_to_sorted().begin(), g.original_to_sorted().end());
    o.counts = g.count_neighbors(index_space::original);
    o.counts_sorted = g.count_neighbors(index_space::sorted);
    o.query_counts = g.query_counts(queries);
    for (auto space : {index_space::original, index_space::sorted}) {
        list_options lo;
        lo.space = space;
        lo.distances = true;
        o.lists.push_back(g.neighbor_lists(lo));  // traversal order: the most fragile
        o.lists.push_back(g.query(queries, lo));
        lo.half = true;
        lo.order = row_order::distance;
        o.lists.push_back(g.neighbor_lists(lo));
        lo.half = false;
        o.lists.push_back(space == index_space::original ? g.nearest(6, lo) : g.query_nearest(queries, 3, lo));
    }
    return o;
}

template <class T>
void expect_same(const outputs<T>& a, const outputs<T>& b, const std::string& what) {
    EXPECT_EQ(a.kind, b.kind) << what;
    EXPECT_TRUE(a.perm == b.perm) << what << ": sorted_to_original differs";
    EXPECT_TRUE(a.inverse == b.inverse) << what << ": original_to_sorted differs";
    EXPECT_TRUE(a.counts == b.counts) << what << ": count_neighbors differs";
    EXPECT_TRUE(a.counts_sorted == b.counts_sorted) << what << ": count_neighbors(sorted) differs";
    EXPECT_TRUE(a.query_counts == b.query_counts) << what << ": query_counts differs";
    ASSERT_EQ(a.lists.size(), b.lists.size());
    for (std::size_t k = 0; k < a.lists.size(); ++k)
        EXPECT_EQ(csr_diff(a.lists[k], b.lists[k]), "") << what << ": list " << k;
}

template <class T, int D>
void invariance_case(const std::vector<T>& pts, T r, grid_options opt, const std::vector<T>& queries,
                     std::vector<grid_kind> kinds = {grid_kind::automatic, grid_kind::uniform,
                                                     grid_kind::hashed}) {
    for (auto kind : kinds) {
        for (double f : {1.0, 0.5}) {
            // automatic and uniform at cell r, hashed at r/2.
            if ((kind == grid_kind::hashed) != (f == 0.5)) continue;
            opt.kind = kind;
            opt.cell_size = double(r) * f;
            SCOPED_TRACE("kind=" + kind_name(kind) + " cell=r*" + std::to_string(f));
            opt.threads = 1;
            const grid<T, D> g1(pts, r, opt);
            ASSERT_EQ(g1.threads(), 1);
            const auto ref = collect<T, D>(g1, queries);
            for (int t : {2, 4}) {
                opt.threads = t;
                const grid<T, D> gt(pts, r, opt);
                EXPECT_EQ(gt.threads(), t);
                expect_same(ref, collect<T, D>(gt, queries), std::to_string(t) + " threads");
            }
            // set_threads + rebuild: the reused structure gives the same bits too.
            grid<T, D> g(pts, r, opt);
            g.set_threads(4);
            g.rebuild(pts);
            expect_same(ref, collect<T, D>(g, queries), "rebuild at 4 threads");
        }
    }
}

// Sizes: the build cuts points into min(threads, N / 4096) chunks and queries into chunks of
// at least 2048 rows, so N >= 16384 gives 4 build chunks at 4 threads.
TEST(OracleThreads, UniformDouble3D) {
    const auto pts = uniform_points<double, 3>(9000, 0, 15, 201);
    invariance_case<double, 3>(pts, 1.0, {}, query_points<double, 3>(pts, 1.0, 2500, {}, 202));
}

TEST(OracleThreads, ClusteredFloat2D) {
    const auto pts = clustered_points<float, 2>(17000, 20, 2.0, -40, 40, 203);
    invariance_case<float, 2>(pts, 0.5f, {}, query_points<float, 2>(pts, 0.5, 2500, {}, 204));
}

// A sparse uniform grid of 160 000 cells: the prefix sum over cells runs in parallel too.
TEST(OracleThreads, SparseUniformFloat2D) {
    const auto pts = uniform_points<float, 2>(17000, 0, 400, 209);
    grid_options opt;
    opt.kind = grid_kind::uniform;
    const grid<float, 2> probe(pts, 1.0f, opt);
    ASSERT_GT(probe.slot_count(), std::size_t(1) << 17);
    invariance_case<float, 2>(pts, 1.0f, opt, query_points<float, 2>(pts, 1.0, 2500, {}, 210),
                              {grid_kind::uniform});
}

TEST(OracleThreads, PeriodicDouble2D) {
    grid_options opt;
    opt.periodic = {20, 11};
    auto pts = uniform_points<double, 2>(10000, 0, 1, 205);
    for (std::size_t i = 0; i < pts.size(); ++i) pts[i] *= opt.periodic[i % 2];
    invariance_case<double, 2>(pts, 0.4, opt, query_points<double, 2>(pts, 0.4, 2500, opt.periodic, 206));
}

// 27 layers of cells along z: an odd number of slabs, whose last one reaches into the first
// and is swept alone; the box spans 18 x 16 x 27 cells, so interior cells skip the image.
TEST(OracleThreads, PeriodicFloat3DOddSlabs) {
    grid_options opt;
    opt.periodic = {9, 8, 13.5};
    auto pts = uniform_points<float, 3>(12000, 0, 1, 211);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const float box = float(opt.periodic[i % 3]);
        pts[i] = std::min(pts[i] * box, std::nextafter(box, 0.0f));  // inside [0, L)
    }
    invariance_case<float, 3>(pts, 0.5f, opt, query_points<float, 3>(pts, 0.5, 2500, opt.periodic, 212),
                              {grid_kind::uniform});
}

TEST(OracleThreads, OutlierFloat3D) {
    auto pts = clustered_points<float, 3>(9000, 8, 1.5, -10, 10, 207);
    const auto queries = query_points<float, 3>(pts, 0.4, 2500, {}, 208);
    append_point<float, 3>(pts, 1e7);
    // A dense grid over 1e7 / 0.4 cells per axis is not an option: hashed and automatic only.
    invariance_case<float, 3>(pts, 0.4f, {}, queries, {grid_kind::automatic, grid_kind::hashed});
}

// Correctness, not only invariance, where slabs of cell layers are fewest and thinnest: boxes
// and extents of 2 reach + 1 to 2 reach + 4 cells on each axis, periodic and open, swept at 2
// and 3 threads against the brute-force oracle. Slabs of one layer run at the same time there,
// each adding partner counts into its neighbor's spill; the oracle tests elsewhere run at 1
// thread. (Periodic boxes of 2 reach + 1 cells once lost pairs here.)
template <int D>
void thin_slabs_case(bool periodic, std::uint64_t seed) {
    for (double cell_in_r : {1.0, 0.5}) {
        const int reach = cell_in_r == 1.0 ? 1 : 2;
        for (int extra = 0; extra <= 3; ++extra) {
            const int cells = 2 * reach + 1 + extra;
            const double side = cells * cell_in_r * 1.0001;  // r = 1: just over `cells` cells
            const std::size_t n = D == 3 ? 700 : 500;
            const auto pts = uniform_points<float, D>(n, 0, side, seed + std::uint64_t(cells));
            grid_options opt;
            opt.kind = grid_kind::uniform;
            opt.cell_size = cell_in_r;
            if (periodic) opt.periodic.assign(D, side);
            for (int threads : {2, 3}) {
                opt.threads = threads;
                SCOPED_TRACE(std::string(periodic ? "periodic" : "open") + " cells=" + std::to_string(cells) +
                             " reach=" + std::to_string(reach) + " threads=" + std::to_string(threads));
                check_all<float, D>(pts, 1.0f, opt, {}, depth::basic);
            }
        }
    }
}

TEST(OracleThreads, ThinSlabsPeriodic3D) { thin_slabs_case<3>(true, 300); }
TEST(OracleThreads, ThinSlabsPeriodic2D) { thin_slabs_case<2>(true, 310); }
TEST(OracleThreads, ThinSlabsOpen3D) { thin_slabs_case<3>(false, 320); }
TEST(OracleThreads, ThinSlabsOpen2D) { thin_slabs_case<2>(false, 330); }

}  // namespace
}  // namespace frnn::test
