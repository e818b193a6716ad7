// The host API around the queries: device info, the validation messenger, errors, the caller's
// buffers and device, results left on the device, determinism, the convenience functions and
// agreement with the CPU grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <limits>

#include "frnn/brute_force.hpp"
#include "frnn/grid.hpp"
#include "oracle/point_sets.hpp"
#include "vulkan_env.hpp"

namespace frnn::vulkan::test {
namespace {

using frnn::test::uniform_points;

class vulkan_api : public vulkan_test {};

TEST_F(vulkan_api, reports_device) {
    const auto& info = ctx().info();
    EXPECT_FALSE(info.name.empty());
    EXPECT_GT(info.max_storage_buffer_range, 0u);
    std::printf("Vulkan device: %s, subgroup size %u, maxStorageBufferRange %llu\n", info.name.c_str(),
                info.subgroup_size, static_cast<unsigned long long>(info.max_storage_buffer_range));
}

TEST_F(vulkan_api, validation_messenger_sees_errors) {
    // Proves that a validation message would fail the tests: an invalid call must be reported.
    if (!validation_layer_installed()) GTEST_SKIP() << "VK_LAYER_KHRONOS_validation is not installed";
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = 64;
    info.usage = 0;  // invalid: VUID-VkBufferCreateInfo-usage-requiredbitmask
    VkBuffer b = VK_NULL_HANDLE;
    vkCreateBuffer(ctx().device(), &info, nullptr, &b);
    if (b) vkDestroyBuffer(ctx().device(), b, nullptr);
    const auto seen = validation_messages().take();
    EXPECT_FALSE(seen.empty()) << "the validation layer reported nothing for an invalid call";
}

TEST_F(vulkan_api, rejects_bad_input_with_reasons) {
    grid<3> g(ctx());
    auto pts = uniform_points<float, 3>(100, 0, 5, 1);
    pts[7 * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(error_of([&] { g.build(pts, 1.0f); }).find("point 7"), std::string::npos);
    pts[7 * 3 + 1] = std::numeric_limits<float>::infinity();
    EXPECT_NE(error_of([&] { g.build(pts, 1.0f); }).find("point 7"), std::string::npos);
    pts[7 * 3 + 1] = 1.0f;
    EXPECT_NE(error_of([&] { g.build(pts, -1.0f); }).find("radius"), std::string::npos);
    EXPECT_NE(error_of([&] { g.build(pts, 0.0f); }).find("radius must be positive"), std::string::npos);
    grid_options periodic;
    periodic.periodic = {5, 1.5, 5};
    EXPECT_NE(error_of([&] { g.build(pts, 1.0f, periodic); }).find("twice the radius"), std::string::npos);
    periodic.periodic = {5, 5};
    EXPECT_NE(error_of([&] { g.build(pts, 1.0f, periodic); }).find("3 lengths"), std::string::npos);
    EXPECT_NE(error_of([&] { g.count_neighbors(); }).find("not built"), std::string::npos);
    grid_options uniform;
    uniform.kind = grid_kind::uniform;
    pts.push_back(1e7f), pts.push_back(1e7f), pts.push_back(1e7f);
    EXPECT_NE(error_of([&] { g.build(pts, 1.0f, uniform); }).find("hashed"), std::string::npos);
    g.build(pts, 1.0f);  // automatic: hashed
    EXPECT_EQ(g.kind(), grid_kind::hashed);
    EXPECT_NE(error_of([&] { g.nearest(0); }).find("k must"), std::string::npos);
    const std::vector<float> bad_query{0, 0, 0, 1, std::numeric_limits<float>::quiet_NaN(), 1};
    EXPECT_NE(error_of([&] { g.query(bad_query); }).find("query point 1"), std::string::npos);
    EXPECT_NE(error_of([&] { g.query_counts(std::vector<float>{1, 2}); }).find("multiple of 3"), std::string::npos);
    EXPECT_NE(error_of([&] { neighbor_lists(ctx(), pts, 4, 1.0f); }).find("dimension"), std::string::npos);
    list_options some_rows;
    some_rows.rows = 10;
    EXPECT_NE(error_of([&] { g.neighbor_lists(some_rows); }).find("CPU grid only"), std::string::npos);
    EXPECT_NE(error_of([&] { g.nearest(2, some_rows); }).find("CPU grid only"), std::string::npos);
}

TEST_F(vulkan_api, splits_or_rejects_beyond_the_binding_limit) {
    // Bindings of at most 16 KiB (4096 pairs): host results come in chunks of rows, identical
    // to unsplit ones; results kept on the device and oversized buffers are rejected.
    context_options o = test_options();
    o.max_binding_bytes = 16384;
    context small(o);
    EXPECT_EQ(small.info().max_storage_buffer_range, 16384u);
    const auto pts = uniform_points<float, 3>(1000, 0, 6, 9);  // ~19 neighbors, ~19,000 pairs
    const auto queries = uniform_points<float, 3>(300, 0, 6, 10);
    grid<3> a(small), b(ctx());
    a.build(pts, 1.0f);
    b.build(pts, 1.0f);
    auto same = [](const csr<float>& x, const csr<float>& y) {
        EXPECT_EQ(x.offsets, y.offsets);
        EXPECT_EQ(x.indices, y.indices);
        EXPECT_EQ(x.distances, y.distances);
    };
    for (auto order : {row_order::none, row_order::index, row_order::distance}) {
        list_options lo;
        lo.order = order;
        lo.distances = order != row_order::index;
        const auto split = a.neighbor_lists(lo);
        EXPECT_GT(split.size() * 4, 3u * 16384u);  // four chunks
        same(split, b.neighbor_lists(lo));
        same(a.query(queries, lo), b.query(queries, lo));
    }
    same(a.nearest(8), b.nearest(8));
    same(a.query_nearest(queries, 5), b.query_nearest(queries, 5));

    const std::string on_device = error_of([&] { a.neighbor_lists_on_device(); });
    EXPECT_NE(on_device.find("maxStorageBufferRange"), std::string::npos) << on_device;
    EXPECT_EQ(a.count_neighbors(), b.count_neighbors());  // still usable after the error
    // Buffers: a device_buffer, a uniform grid's cells, and a caller's buffer too small.
    EXPECT_NE(error_of([&] { device_buffer huge(small, 16385); }).find("maxStorageBufferRange"),
              std::string::npos);
    grid_options uniform;
    uniform.kind = grid_kind::uniform;
    uniform.domain_min = {0, 0, 0};
    uniform.domain_max = {30, 30, 30};
    EXPECT_NE(error_of([&] { a.build(pts, 1.0f, uniform); }).find("use the hashed grid"), std::string::npos);
    device_buffer tiny(ctx(), 64);
    EXPECT_NE(error_of([&] { b.build(tiny.view(), 100, 1.0f); }).find("buffer holds"), std::string::npos);
}

TEST_F(vulkan_api, builds_from_the_callers_buffer) {
    const auto pts = uniform_points<float, 3>(1200, 0, 9, 2);
    device_buffer coords(ctx(), pts.size() * sizeof(float) + 256, "coords");
    coords.upload(pts.data(), pts.size() * sizeof(float), 256);  // at an offset
    grid<3> from_buffer(ctx()), from_host(ctx());
    buffer_view view = coords.view();
    view.offset = 256;
    view.size = pts.size() * sizeof(float);
    from_buffer.build(view, pts.size() / 3, 1.0f);
    from_host.build(pts, 1.0f);
    list_options o;
    o.distances = true;
    const auto a = from_buffer.neighbor_lists(o), b = from_host.neighbor_lists(o);
    EXPECT_EQ(a.offsets, b.offsets);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.distances, b.distances);
    EXPECT_GT(a.size(), 0u);
}

TEST_F(vulkan_api, wraps_the_callers_device) {
    external_device ext;
    ext.instance = ctx().instance();
    ext.physical_device = ctx().physical_device();
    ext.device = ctx().device();
    ext.queue = ctx().queue();
    ext.queue_family = ctx().queue_family();
    const auto pts = uniform_points<float, 2>(800, 0, 20, 3);
    std::vector<std::uint32_t> a, b;
    {
        context wrapped(ext);
        EXPECT_EQ(wrapped.device(), ctx().device());
        a = count_neighbors(wrapped, pts, 2, 1.0f);
    }  // destroys nothing of the caller's
    b = count_neighbors(ctx(), pts, 2, 1.0f);
    external_device bad = ext;
    bad.queue_family = 1000;
    EXPECT_THROW(context{bad}, frnn::error);
    EXPECT_EQ(a, b);
    const auto ref = brute_force_lists<float, 2>(pts, pts, 1.0f, true);
    for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], ref.offsets[i + 1] - ref.offsets[i]);
}

TEST_F(vulkan_api, lists_left_on_the_device) {
    const auto pts = uniform_points<float, 3>(900, 0, 8, 4);
    grid<3> g(ctx());
    g.build(pts, 1.0f);
    list_options o;
    o.order = row_order::index;
    o.distances = true;
    const auto host = g.neighbor_lists(o);
    const auto dev = g.neighbor_lists_on_device(o);
    ASSERT_EQ(dev.rows, 900u);
    ASSERT_EQ(dev.pairs, host.size());
    std::vector<std::uint32_t> offsets(dev.rows + 1), indices(dev.pairs);
    std::vector<float> d2(dev.pairs);
    ctx().download(dev.offsets, offsets.data(), offsets.size() * 4);
    ctx().download(dev.indices, indices.data(), indices.size() * 4);
    ctx().download(dev.distances_squared, d2.data(), d2.size() * 4);
    for (std::size_t i = 0; i <= dev.rows; ++i) ASSERT_EQ(offsets[i], host.offsets[i]);
    EXPECT_TRUE(std::equal(indices.begin(), indices.end(), host.indices.begin(), host.indices.end()));
    for (std::size_t k = 0; k < d2.size(); ++k) ASSERT_EQ(std::sqrt(d2[k]), host.distances[k]);
}

TEST_F(vulkan_api, identical_results_run_to_run) {
    // Many points per cell, so the atomics' order inside cells varies between runs.
    const auto pts = frnn::test::clustered_points<float, 3>(2000, 3, 0.7, 0, 10, 5);
    grid<3> g(ctx());
    list_options o;
    o.distances = true;  // traversal order
    g.build(pts, 0.6f);
    const auto perm = g.sorted_to_original();
    const auto first = g.neighbor_lists(o);
    const auto near = g.nearest(7);
    for (int run = 0; run < 3; ++run) {
        g.build(pts, 0.6f);
        EXPECT_EQ(g.sorted_to_original(), perm);
        const auto again = g.neighbor_lists(o);
        EXPECT_EQ(again.indices, first.indices);
        EXPECT_EQ(again.distances, first.distances);
        EXPECT_EQ(g.nearest(7).indices, near.indices);
    }
}

TEST_F(vulkan_api, agrees_with_the_cpu_grid) {
    // A W1-style jittered lattice, the SPH case, against frnn::grid<float, 3>.
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    std::vector<float> pts;
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x)
                for (int v : {x, y, z}) pts.push_back(float(v + jitter(rng)));
    frnn::grid<float, 3> cpu(pts, 2.0f);
    list_options o;
    o.order = row_order::index;
    o.distances = true;
    const auto want = cpu.neighbor_lists(o);
    for (grid_kind kind : {grid_kind::uniform, grid_kind::hashed}) {
        grid_options go;
        go.kind = kind;
        const auto got = neighbor_lists(ctx(), pts, 3, 2.0f, go, o);
        EXPECT_EQ(got.offsets, want.offsets);
        EXPECT_EQ(got.indices, want.indices);
        EXPECT_EQ(got.distances, want.distances);
    }
    const auto counts = cpu.count_neighbors();
    EXPECT_EQ(count_neighbors(ctx(), pts, 3, 2.0f), counts);
}

TEST_F(vulkan_api, dispatches_split_into_rows) {
    // Rows of 3 workgroups: every dispatch (build, scan levels, queries, a user kernel's
    // frnn_invocation_index) runs as a 2D grid of groups, with spare groups in the last row.
    context_options o = test_options();
    o.max_groups_per_row = 3;
    context split(o);
    const auto pts = uniform_points<float, 3>(5000, 0, 12, 8);
    grid_options go;
    go.kind = grid_kind::uniform;
    go.domain_min = {-40, -40, -40};  // ~1.3M cells: scan levels of 1300 and 2 blocks
    go.domain_max = {70, 70, 70};
    list_options lo;
    lo.distances = true;
    lo.order = row_order::distance;
    const auto a = neighbor_lists(split, pts, 3, 1.0f, go, lo);
    const auto b = neighbor_lists(ctx(), pts, 3, 1.0f, go, lo);
    EXPECT_EQ(a.offsets, b.offsets);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.distances, b.distances);
    grid<3> g(split);
    g.build(pts, 1.0f);
    EXPECT_EQ(g.nearest(3).indices, [&] {
        grid<3> h(ctx());
        h.build(pts, 1.0f);
        return h.nearest(3).indices;
    }());
}

TEST_F(vulkan_api, search_covers_the_query_command) {
    // search(): what `frnn query --backend vulkan` calls, against the CPU grid.
    const auto data = uniform_points<float, 3>(1500, 0, 10, 6);
    const auto queries = uniform_points<float, 3>(200, -1, 11, 7);
    frnn::grid<float, 3> cpu(data, 1.0f);
    list_options o;
    o.distances = true;
    o.order = row_order::index;
    auto same = [](const csr<float>& a, const csr<float>& b) {
        EXPECT_EQ(a.offsets, b.offsets);
        EXPECT_EQ(a.indices, b.indices);
        EXPECT_EQ(a.distances, b.distances);
    };
    const auto all = search(ctx(), data, 3, 1.0f, {}, o);
    same(all.lists, cpu.neighbor_lists(o));
    EXPECT_EQ(all.kind, grid_kind::uniform);
    EXPECT_GT(all.slots, 0u);
    same(search(ctx(), data, 3, 1.0f, {}, o, {}, 4).lists, cpu.nearest(4, o));
    same(search(ctx(), data, 3, 1.0f, {}, o, queries).lists, cpu.query(queries, o));
    same(search(ctx(), data, 3, 1.0f, {}, o, queries, 2).lists, cpu.query_nearest(queries, 2, o));
}

TEST_F(vulkan_api, loop_limits_fail_loudly) {
    // 20,000 points within r of each other: each row loops over 20,000 candidates, more than
    // lavapipe runs before stopping a group's loops (it then returned counts of 16,383). Either
    // exact counts (a driver without the limit) or an error naming it, never cut counts.
    const std::size_t n = 20000;
    const auto pts = uniform_points<float, 3>(n, 0, 0.5, 61);
    grid<3> g(ctx());
    g.build(pts, 1.0f);
    std::vector<std::uint32_t> counts;
    const std::string err = error_of([&] { counts = g.count_neighbors(); });
    if (counts.empty()) {
        EXPECT_NE(err.find("stopped a shader loop"), std::string::npos) << err;
    } else {
        EXPECT_EQ(counts, std::vector<std::uint32_t>(n, std::uint32_t(n - 1)));
    }
    if (ctx().info().is_cpu) std::printf("%s: %s\n", ctx().info().name.c_str(), err.c_str());
}

}  // namespace
}  // namespace frnn::vulkan::test
