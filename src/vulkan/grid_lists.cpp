// Vulkan grid queries: counts, scans and CSR lists (or k nearest) of the grid's own points or
// of external query points, on the device or brought to the host in chunks.
#include <algorithm>
#include <cstring>
#include <string>
#include "grid_state.hpp"

namespace frnn::vulkan::detail {

grid_state::row_source grid_state::upload_queries(std::span<const float> q, const char* what) {
    if (q.size() % dim != 0)
        throw error(std::string("vulkan::grid::") + what + ": " + std::to_string(q.size()) +
                    " query coordinates is not a multiple of " + std::to_string(dim));
    const std::size_t count = q.size() / dim;
    if (count >= 0x7FFFFFFFu) throw error(std::string("vulkan::grid::") + what + ": too many query points");
    for (std::size_t i = 0; i < q.size(); ++i) {
        if (!std::isfinite(q[i]))
            throw error(std::string("vulkan::grid::") + what + ": query point " + std::to_string(i / dim) +
                        " has a non-finite coordinate (axis " + std::to_string(i % dim) + ")");
    }
    std::vector<float> scaled;
    if (geometry.scale != 1) {
        // In search units, wrapped and multiplied as the oracle does (unscaled queries are
        // wrapped on the device, by frnn_begin). A far query on an open axis may overflow when
        // s > 1: the oracle's differences are then infinite (no neighbors), and a point at 2^127
        // has none either, since scaled data lie below 2^126 (search_scale) and r*s is far smaller.
        scaled.resize(q.size());
        for (std::size_t i = 0; i < q.size(); ++i) {
            const std::size_t a = i % std::size_t(dim);
            const float v = geometry.wraps[a] ? wrap_into_box(q[i], geometry.box[a] / geometry.scale) : q[i];
            const float y = v * geometry.scale;
            scaled[i] = std::isinf(y) ? std::copysign(0x1p127f, q[i]) : y;
        }
        q = scaled;
    }
    ensure(query_pos, std::max<std::size_t>(q.size() * 4, 4), "query points");
    dev->upload(query_pos.view(), q.data(), q.size() * 4);
    return {count, query_pos.view(0, std::max<std::size_t>(q.size() * 4, 4)), true};
}

void grid_state::record_count(std::uint32_t f, std::uint32_t cap, const row_source& src) {
    const auto g = grid_views();
    const std::uint32_t push[3] = {f | (src.external ? flag_external : 0u), cap, std::uint32_t(src.rows)};
    dev->dispatch(dev->get(shader::count, dim, kind_code()),
                  {g[0], g[1], g[2], g[3], g[4], counts.view(0, src.rows * 4), src.queries, status_word()}, push,
                  sizeof(push),
                  groups_for(src.rows, group_size));
}

std::size_t grid_state::count_and_scan(std::uint32_t f, std::uint32_t cap, const char* what, const row_source& src) {
    rows = src.rows;
    const std::size_t rows_bytes = (rows + 1) * 4;
    ensure(counts, rows_bytes, "neighbor counts");
    ensure(scan_scratch, scan_scratch_bytes(rows + 1), "scan scratch");
    dev->begin();
    clear_status();
    dev->fill(counts.view(0, rows_bytes), 0u);
    record_count(f, cap, src);
    record_scan(counts.view(0, rows_bytes), rows + 1, 0);
    dev->submit();
    check_status(what);
    std::uint32_t total = 0;
    dev->download(counts.view(rows * 4, 4), &total, 4);
    if (total == 0xFFFFFFFFu)
        throw error(std::string("vulkan::grid::") + what + ": 2^32 or more pairs; query fewer points");
    return total;
}

grid_state::list_plan grid_state::plan(const list_options& o, std::size_t k, const row_source& src) const {
    if (o.rows != list_options::all_rows) throw error("vulkan::grid: list_options.rows (rows for some points only) runs on the CPU grid only");
    list_plan p;
    p.nearest = k > 0;
    p.need_d2 = o.distances || p.nearest || o.order == row_order::distance;
    p.flags = flags(o) | (p.need_d2 ? flag_distances : 0u) | (src.external ? flag_external : 0u);
    p.cap = p.nearest ? std::uint32_t(std::min<std::size_t>(k, 0xFFFFFFFFu)) : 0xFFFFFFFFu;
    p.sort = p.nearest ? 0u : o.order == row_order::distance ? 2u : o.order == row_order::index ? 1u : 0u;
    return p;
}

// Fills rows [r0, r1) (whose pairs, `chunk` of them, start at offsets[r0]) into the start of
// the index and distance buffers, sorting them when asked.
void grid_state::fill_rows(const list_plan& p, const row_source& src, std::size_t r0, std::size_t r1,
                           std::size_t chunk, const char* what) {
    ensure(indices, chunk * 4, "neighbor indices");
    if (p.need_d2) ensure(dist2, chunk * 4, "neighbor distances");
    const auto g = grid_views();
    const buffer_view offsets = counts.view(0, (rows + 1) * 4);
    const buffer_view idx = indices.view(0, std::max<std::size_t>(chunk * 4, 4));
    const buffer_view d2 = p.need_d2 ? dist2.view(0, std::max<std::size_t>(chunk * 4, 4)) : unused_binding();
    const std::uint32_t push[5] = {p.flags, p.cap, std::uint32_t(rows), std::uint32_t(r0), std::uint32_t(r1)};
    dev->begin();
    clear_status();
    if (chunk > 0) {
        dev->dispatch(dev->get(p.nearest ? shader::knn : shader::fill, dim, kind_code()),
                      {g[0], g[1], g[2], g[3], g[4], offsets, idx, d2, src.queries, status_word()}, push,
                      sizeof(push), groups_for(rows, group_size));
        if (p.sort) {
            const std::uint32_t sp[4] = {std::uint32_t(r1 - r0), p.sort, p.need_d2 ? 1u : 0u, std::uint32_t(r0)};
            dev->dispatch(dev->get(shader::sort_rows, dim), {offsets, idx, d2, status_word()}, sp, sizeof(sp),
                          groups_for(r1 - r0, group_size));
        }
    }
    dev->submit();
    check_status(what);
}

std::string grid_state::too_many_pairs(const char* what, std::size_t count) const {
    const std::size_t limit = dev->info().max_storage_buffer_range;
    return std::string("vulkan::grid::") + what + ": " + std::to_string(count) + " pairs need " +
           std::to_string(count * 4) + " bytes per array, more than one storage buffer of this device holds (" +
           "maxStorageBufferRange " + std::to_string(limit) + " bytes)";
}

// Counts, scans and fills all rows on the device (k > 0: k nearest); one binding must hold them.
void grid_state::lists_on_device(const list_options& o, std::size_t k, const row_source& src, const char* what) {
    const list_plan p = plan(o, k, src);
    pairs = count_and_scan(p.flags, p.cap, what, src);
    if (pairs * 4 > dev->info().max_storage_buffer_range)
        throw error(too_many_pairs(what, pairs) + "; use the host results (split automatically), query fewer "
                                                   "points or a smaller radius");
    fill_rows(p, src, 0, rows, pairs, what);
}

// Lists to the host: rows are filled in chunks whose pairs fit one storage buffer, so results
// larger than maxStorageBufferRange still work (one more pass over the points per chunk).
csr<float> grid_state::lists_to_host(const list_options& o, std::size_t k, const row_source& src, const char* what) {
    const list_plan p = plan(o, k, src);
    pairs = count_and_scan(p.flags, p.cap, what, src);
    std::vector<std::uint32_t> off(rows + 1);
    dev->download(counts.view(0, (rows + 1) * 4), off.data(), (rows + 1) * 4);
    csr<float> out;
    out.offsets.assign(off.begin(), off.end());
    out.indices.resize(pairs);
    if (o.distances) out.distances.resize(pairs);
    const std::size_t per_chunk = dev->info().max_storage_buffer_range / 4;
    for (std::size_t r0 = 0; r0 < rows;) {
        // The most rows from r0 whose pairs fit one buffer.
        const std::size_t r1 =
            std::size_t(std::upper_bound(off.begin() + r0 + 1, off.end(), std::uint64_t(off[r0]) + per_chunk,
                                         [](std::uint64_t v, std::uint32_t e) { return v < e; }) -
                        off.begin()) - 1;
        if (r1 == r0) throw error(too_many_pairs(what, off[r0 + 1] - off[r0]) + " in row " + std::to_string(r0));
        const std::size_t chunk = off[r1] - off[r0];
        fill_rows(p, src, r0, r1, chunk, what);
        dev->download(indices.view(0, chunk * 4), out.indices.data() + off[r0], chunk * 4);
        if (o.distances) {
            float* d = out.distances.data() + off[r0];
            dev->download(dist2.view(0, chunk * 4), d, chunk * 4);
            // The host's sqrt is correctly rounded, so distances match the CPU grid bit for bit;
            // 1/s brings them back to the caller's units (as distance_test::distance does).
            const float inv = 1.0f / geometry.scale;
            for (std::size_t e = 0; e < chunk; ++e) d[e] = std::sqrt(d[e]) * inv;
        }
        r0 = r1;
    }
    return out;
}

csr<float> grid_state::query_lists(std::span<const float> queries, std::size_t k, const list_options& o,
                                   const char* what) {
    const auto src = upload_queries(queries, what);
    if (src.rows == 0) return {};
    if (n == 0) {  // an empty grid: empty rows
        csr<float> empty;
        empty.offsets.assign(src.rows + 1, 0);
        return empty;
    }
    return lists_to_host(o, k, src, what);
}

}  // namespace frnn::vulkan::detail
