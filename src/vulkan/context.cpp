// frnn::vulkan::context, device_buffer, kernel and the host-array convenience functions.
#include <chrono>
#include <string>

#include "device.hpp"
#include "frnn/vulkan.hpp"

namespace frnn::vulkan {

context::context(const context_options& options) : impl_(std::make_unique<detail::device>(options)) {}
context::context(const external_device& device) : impl_(std::make_unique<detail::device>(device)) {}
context::~context() = default;

const device_info& context::info() const { return impl_->info(); }
VkInstance context::instance() const { return impl_->instance(); }
VkDevice context::device() const { return impl_->handle(); }
VkPhysicalDevice context::physical_device() const { return impl_->physical(); }
VkQueue context::queue() const { return impl_->queue(); }
std::uint32_t context::queue_family() const { return impl_->family(); }

void context::upload(buffer_view dst, const void* data, std::size_t bytes) {
    if (bytes > dst.size) throw error("vulkan::context::upload: " + std::to_string(bytes) +
                                      " bytes into a range of " + std::to_string(dst.size));
    impl_->upload(dst, data, bytes);
}
void context::download(buffer_view src, void* data, std::size_t bytes) const {
    if (bytes > src.size) throw error("vulkan::context::download: " + std::to_string(bytes) +
                                      " bytes from a range of " + std::to_string(src.size));
    impl_->download(src, data, bytes);
}

// ---------------------------------------------------------------------------------------------

device_buffer::device_buffer(context& ctx, std::size_t bytes, const std::string& what)
    : impl_(std::make_unique<detail::buffer>(ctx.impl(), bytes, detail::buffer::kind::storage, what)) {
    // Defined contents (zeros), so reading a part never written is not undefined.
    ctx.impl().begin();
    ctx.impl().fill(impl_->view(), 0u);
    ctx.impl().submit();
    dev_ = &ctx.impl();
}
device_buffer::~device_buffer() = default;
device_buffer::device_buffer(device_buffer&&) noexcept = default;
device_buffer& device_buffer::operator=(device_buffer&&) noexcept = default;

buffer_view device_buffer::view() const { return impl_->view(); }
std::size_t device_buffer::size() const { return impl_->size(); }

void device_buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
    if (offset + bytes > size())
        throw error("vulkan::device_buffer::upload: " + std::to_string(bytes) + " bytes at offset " +
                    std::to_string(offset) + " overrun the buffer of " + std::to_string(size()));
    dev_->upload(impl_->view(offset, bytes), data, bytes);
}

void device_buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
    if (offset + bytes > size())
        throw error("vulkan::device_buffer::download: " + std::to_string(bytes) + " bytes at offset " +
                    std::to_string(offset) + " overrun the buffer of " + std::to_string(size()));
    dev_->download(impl_->view(offset, bytes), data, bytes);
}

// ---------------------------------------------------------------------------------------------

kernel::kernel(context& ctx, std::span<const std::uint32_t> spirv, std::size_t user_buffers,
               std::uint32_t push_bytes)
    : ctx_(&ctx), user_buffers_(user_buffers), push_bytes_(push_bytes), spirv_(spirv.begin(), spirv.end()) {
    if (spirv.empty() || spirv[0] != 0x07230203u)
        throw error("vulkan::kernel: the code is not SPIR-V (magic number missing)");
    // Compile now for the uniform grid, so a bad module fails here rather than at run().
    programs_[0] = std::make_unique<detail::program>(ctx.impl(), spirv_, std::uint32_t(5 + user_buffers),
                                                     push_bytes, "user kernel", detail::kind_constant::uniform);
}
kernel::~kernel() = default;
kernel::kernel(kernel&&) noexcept = default;
kernel& kernel::operator=(kernel&&) noexcept = default;

template <int D>
void kernel::run(const grid<D>& g, std::span<const buffer_view> buffers, std::size_t groups,
                 std::span<const std::byte> push) const {
    if (&g.owner() != ctx_) throw error("vulkan::kernel::run: the grid belongs to another context");
    if (buffers.size() != user_buffers_)
        throw error("vulkan::kernel::run: " + std::to_string(buffers.size()) + " buffers given, the kernel takes " +
                    std::to_string(user_buffers_));
    if (push.size() > push_bytes_)
        throw error("vulkan::kernel::run: " + std::to_string(push.size()) +
                    " push-constant bytes given, the kernel declared " + std::to_string(push_bytes_));
    const auto grid_buffers = g.shader_buffers();
    std::vector<buffer_view> all(grid_buffers.begin(), grid_buffers.end());
    all.insert(all.end(), buffers.begin(), buffers.end());
    auto& dev = ctx_->impl();
    auto& program = programs_[g.shader_kind()];
    if (!program)
        program = std::make_unique<detail::program>(dev, spirv_, std::uint32_t(5 + user_buffers_), push_bytes_,
                                                    "user kernel", detail::kind_constant(g.shader_kind()));
    dev.begin();
    dev.dispatch(*program, all, push.data(), push.size(), groups);
    dev.submit();
}

template void kernel::run<2>(const grid<2>&, std::span<const buffer_view>, std::size_t,
                             std::span<const std::byte>) const;
template void kernel::run<3>(const grid<3>&, std::span<const buffer_view>, std::size_t,
                             std::span<const std::byte>) const;

// ---------------------------------------------------------------------------------------------

namespace {
void check_dim(int dim, const char* what) {
    if (dim != 2 && dim != 3)
        throw error(std::string("vulkan::") + what + ": dimension must be 2 or 3, got " + std::to_string(dim));
}
}  // namespace

csr<float> neighbor_lists(context& ctx, std::span<const float> coords, int dim, float radius,
                          const grid_options& grid_opts, const list_options& lists) {
    check_dim(dim, "neighbor_lists");
    if (dim == 2) {
        grid<2> g(ctx);
        g.build(coords, radius, grid_opts);
        return g.neighbor_lists(lists);
    }
    grid<3> g(ctx);
    g.build(coords, radius, grid_opts);
    return g.neighbor_lists(lists);
}

csr<float> neighbor_lists(std::span<const float> coords, int dim, float radius,
                          const grid_options& grid_opts, const list_options& lists) {
    context ctx;
    return neighbor_lists(ctx, coords, dim, radius, grid_opts, lists);
}

namespace {
template <int D>
search_result search_in(context& ctx, std::span<const float> coords, float radius, const grid_options& go,
                        const list_options& lo, std::span<const float> queries, std::size_t k) {
    using clock = std::chrono::steady_clock;
    const auto ms = [](clock::time_point a, clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    search_result out;
    const auto t0 = clock::now();
    grid<D> g(ctx);
    g.build(coords, radius, go);
    const auto t1 = clock::now();
    if (queries.empty())
        out.lists = k ? g.nearest(k, lo) : g.neighbor_lists(lo);
    else
        out.lists = k ? g.query_nearest(queries, k, lo) : g.query(queries, lo);
    const auto t2 = clock::now();
    out.kind = g.kind();
    out.slots = g.slot_count();
    out.build_ms = ms(t0, t1);
    out.query_ms = ms(t1, t2);
    return out;
}
}  // namespace

search_result search(context& ctx, std::span<const float> coords, int dim, float radius,
                     const grid_options& grid_opts, const list_options& lists, std::span<const float> queries,
                     std::size_t k) {
    check_dim(dim, "search");
    return dim == 2 ? search_in<2>(ctx, coords, radius, grid_opts, lists, queries, k)
                    : search_in<3>(ctx, coords, radius, grid_opts, lists, queries, k);
}

std::vector<std::uint32_t> count_neighbors(context& ctx, std::span<const float> coords, int dim,
                                           float radius, const grid_options& grid_opts) {
    check_dim(dim, "count_neighbors");
    if (dim == 2) {
        grid<2> g(ctx);
        g.build(coords, radius, grid_opts);
        return g.count_neighbors();
    }
    grid<3> g(ctx);
    g.build(coords, radius, grid_opts);
    return g.count_neighbors();
}

}  // namespace frnn::vulkan
