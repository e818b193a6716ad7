// frnn::vulkan::grid: the public class, forwarding to its state (grid_state.hpp), whose build
// and queries are recorded as dispatches of the embedded shaders.
#include <memory>

#include "grid_state.hpp"

namespace frnn::vulkan {

template <int D>
grid<D>::grid(context& ctx) : state_(std::make_unique<detail::grid_state>()) {
    state_->ctx = &ctx;
    state_->dev = &ctx.impl();
    state_->dim = D;
}

template <int D>
grid<D>::~grid() = default;
template <int D>
grid<D>::grid(grid&&) noexcept = default;
template <int D>
grid<D>& grid<D>::operator=(grid&&) noexcept = default;

template <int D>
void grid<D>::build(std::span<const float> coords, float radius, const grid_options& options) {
    try {
        state_->build_from_host(coords, radius, options);
    } catch (const std::bad_alloc&) {
        state_->clear();  // documented: empty after bad_alloc, wherever it happened
        throw;
    }
}

template <int D>
void grid<D>::build(buffer_view coords, std::size_t n, float radius, const grid_options& options) {
    try {
        state_->build_from_device(coords, n, radius, options);
    } catch (const std::bad_alloc&) {
        state_->clear();
        throw;
    }
}

template <int D>
std::size_t grid<D>::size() const { return state_->n; }
template <int D>
float grid<D>::radius() const { return state_->radius; }
template <int D>
float grid<D>::search_scale() const { return state_->geometry.scale; }
template <int D>
grid_kind grid<D>::kind() const { return state_->geometry.kind; }
template <int D>
std::size_t grid<D>::slot_count() const { return state_->geometry.slots; }
template <int D>
const grid_geometry<float>& grid<D>::geometry() const { return state_->geometry; }
template <int D>
context& grid<D>::owner() const { return *state_->ctx; }

template <int D>
std::vector<std::uint32_t> grid<D>::sorted_to_original() const {
    auto& s = *state_;
    s.check_built("sorted_to_original");
    std::vector<std::uint32_t> out(s.n);
    s.dev->download(s.perm.view(0, s.n * 4), out.data(), s.n * 4);
    return out;
}

template <int D>
std::vector<std::uint32_t> grid<D>::count_neighbors(index_space space) const {
    auto& s = *state_;
    s.check_built("count_neighbors");
    std::vector<std::uint32_t> out(s.n);
    if (s.n == 0) return out;
    list_options o;
    o.space = space;
    s.ensure(s.counts, (s.n + 1) * 4, "neighbor counts");
    s.dev->begin();
    s.clear_status();
    s.record_count(s.flags(o), 0xFFFFFFFFu, s.own_rows());
    s.dev->submit();
    s.check_status("count_neighbors");
    s.dev->download(s.counts.view(0, s.n * 4), out.data(), s.n * 4);
    return out;
}

template <int D>
csr<float> grid<D>::neighbor_lists(const list_options& options) const {
    auto& s = *state_;
    s.check_built("neighbor_lists");
    if (s.n == 0) return {};
    return s.lists_to_host(options, 0, s.own_rows(), "neighbor_lists");
}

template <int D>
csr<float> grid<D>::nearest(std::size_t k, const list_options& options) const {
    auto& s = *state_;
    s.check_built("nearest");
    if (k == 0) throw error("vulkan::grid::nearest: k must be at least 1");
    if (s.n == 0) return {};
    return s.lists_to_host(options, k, s.own_rows(), "nearest");
}

// Queries from other points: `half` and `self` do not apply (as on the CPU).
namespace {
list_options for_queries(list_options o) {
    o.half = false;
    o.self = false;
    return o;
}
}  // namespace

template <int D>
std::vector<std::uint32_t> grid<D>::query_counts(std::span<const float> queries) const {
    auto& s = *state_;
    s.check_built("query_counts");
    const auto src = s.upload_queries(queries, "query_counts");
    std::vector<std::uint32_t> out(src.rows);
    if (src.rows == 0 || s.n == 0) return out;
    s.ensure(s.counts, (src.rows + 1) * 4, "neighbor counts");
    s.dev->begin();
    s.clear_status();
    s.record_count(s.flags(list_options{}), 0xFFFFFFFFu, src);
    s.dev->submit();
    s.check_status("query_counts");
    s.dev->download(s.counts.view(0, src.rows * 4), out.data(), src.rows * 4);
    return out;
}

template <int D>
csr<float> grid<D>::query(std::span<const float> queries, const list_options& options) const {
    state_->check_built("query");
    return state_->query_lists(queries, 0, for_queries(options), "query");
}

template <int D>
csr<float> grid<D>::query_nearest(std::span<const float> queries, std::size_t k, const list_options& options) const {
    state_->check_built("query_nearest");
    if (k == 0) throw error("vulkan::grid::query_nearest: k must be at least 1");
    return state_->query_lists(queries, k, for_queries(options), "query_nearest");
}

template <int D>
typename grid<D>::device_csr grid<D>::neighbor_lists_on_device(const list_options& options) {
    auto& s = *state_;
    s.check_built("neighbor_lists_on_device");
    device_csr out;
    out.rows = s.n;
    if (s.n == 0) return out;
    s.lists_on_device(options, 0, s.own_rows(), "neighbor_lists_on_device");
    out.pairs = s.pairs;
    out.offsets = s.counts.view(0, (s.n + 1) * 4);
    out.indices = s.indices.view(0, std::max<std::size_t>(s.pairs * 4, 4));
    if (options.distances) out.distances_squared = s.dist2.view(0, std::max<std::size_t>(s.pairs * 4, 4));
    return out;
}

template <int D>
std::uint32_t grid<D>::shader_kind() const {
    state_->check_built("shader_kind");
    return std::uint32_t(state_->kind_code());
}

template <int D>
std::array<buffer_view, 5> grid<D>::shader_buffers() const {
    state_->check_built("shader_buffers");
    return state_->grid_views();
}

template class grid<2>;
template class grid<3>;

}  // namespace frnn::vulkan
