// frnn::vulkan: the neighbor search on a GPU (or any Vulkan device) with compute shaders.
//
// A context owns (or wraps) a Vulkan device and queue. A vulkan::grid<D> is built on the device
// from host coordinates or from the caller's own VkBuffer (no copy): bounding box, insertion
// with atomics, multi-level exclusive scan, scatter and a stable pass: 7-9 dispatches for 1M
// points. Queries run on the device: neighbor counts, CSR neighbor lists (count, scan, fill)
// and the k nearest within the radius, of the grid's points or of other query points. Results equal the CPU grid's pairs exactly (same float
// formula, `precise` arithmetic), rows in a deterministic order. Float coordinates, 2D and 3D,
// uniform and hashed grids, periodic boxes (minimum image, as on the CPU).
// User shaders loop over neighbors with the GLSL include frnn/grid.glsl (see kernel).
//
// Neighbors: |x_i - x_j| <= r, the real radius, i != j (self only on request).
// Complexity: build O(N + cells) work; a query visits the cells within r of each point.
// Every call records its commands, submits them and waits (synchronous); data passed in as a
// buffer_view must be complete before the call (its writes made visible, e.g. by waiting on the
// queue). Thread safety: a context and everything made from it are used from one thread at a
// time; a wrapped queue must not be used by others during a call (Vulkan's external
// synchronization of queues).
// Errors: frnn::error, with the reason (no Vulkan driver, no compute device, a buffer larger
// than the device's maxStorageBufferRange, non-finite coordinates, a failing Vulkan call).
// Extreme radii (r^2 beyond float's range) are searched with the search scale of
// frnn/search_scale.hpp, exactly as the CPU grid and the brute-force oracle do.
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/error.hpp"
#include "frnn/grid_geometry.hpp"
#include "frnn/options.hpp"

namespace frnn::vulkan {

namespace detail {
class device;
class buffer;
struct grid_state;
class program;
}  // namespace detail

enum class severity { verbose, info, warning, error };
/// Receives the messages of VK_EXT_debug_utils (validation layers) for a context.
using message_callback = std::function<void(severity, const std::string&)>;

struct context_options {
    /// Enables VK_LAYER_KHRONOS_validation when it is installed (VK_INSTANCE_LAYERS works too).
    bool validation = false;
    /// When set, a debug-utils messenger forwards every message to it.
    message_callback on_message;
    /// Index into vkEnumeratePhysicalDevices; -1: the first device with a compute queue.
    int device_index = -1;
    /// Larger dispatches are split into rows of this many workgroups (1 to 65535, the limit
    /// every device supports). Tests set it small to exercise the split on small inputs.
    std::uint32_t max_groups_per_row = 65535;
    /// Largest storage buffer frnn binds, in bytes: 0 means the device's maxStorageBufferRange;
    /// smaller values make tests split lists and reject oversized buffers on small inputs.
    std::uint64_t max_binding_bytes = 0;
};

/// A device the caller created and keeps owning: frnn uses it and destroys none of it. It needs
/// Vulkan 1.1 and a queue family with compute support; no features or extensions.
struct external_device {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;      ///< a queue with compute support
    std::uint32_t queue_family = 0;
};

struct device_info {
    std::string name;
    std::uint32_t api_version = 0;
    std::uint32_t subgroup_size = 0;             ///< 0 when unknown (wrapped devices)
    std::uint64_t max_storage_buffer_range = 0;  ///< largest binding frnn uses (lavapipe: 128 MiB)
    bool is_cpu = false;                         ///< a software driver such as lavapipe
};

/// A range of a VkBuffer (created with VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) owned elsewhere.
struct buffer_view {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;  ///< bytes
};

class context {
public:
    /// Creates an instance and a device on the first compute-capable physical device.
    explicit context(const context_options& options = {});
    /// Wraps the caller's device and queue.
    explicit context(const external_device& device);
    ~context();
    context(const context&) = delete;
    context& operator=(const context&) = delete;

    const device_info& info() const;
    VkInstance instance() const;
    VkDevice device() const;
    VkPhysicalDevice physical_device() const;
    VkQueue queue() const;
    std::uint32_t queue_family() const;

    /// Copies between the host and any storage buffer range on this device (synchronous).
    void upload(buffer_view dst, const void* data, std::size_t bytes);
    void download(buffer_view src, void* data, std::size_t bytes) const;

private:
    // frnn's own Vulkan classes reach the device behind the context; users never need it.
    friend class device_buffer;
    friend class kernel;
    template <int D>
    friend class grid;
    detail::device& impl() const { return *impl_; }

    std::unique_ptr<detail::device> impl_;
};

/// A storage buffer owned by frnn on the context's device, for data you bring (inputs of
/// grid::build or of a kernel) or read back.
class device_buffer {
public:
    device_buffer(context& ctx, std::size_t bytes, const std::string& what = "buffer");
    ~device_buffer();
    device_buffer(device_buffer&&) noexcept;
    device_buffer& operator=(device_buffer&&) noexcept;

    buffer_view view() const;
    std::size_t size() const;
    void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
    void download(void* data, std::size_t bytes, std::size_t offset = 0) const;
    template <class U>
    std::vector<U> download_as() const {
        std::vector<U> out(size() / sizeof(U));
        download(out.data(), out.size() * sizeof(U));
        return out;
    }

private:
    std::unique_ptr<detail::buffer> impl_;
    detail::device* dev_ = nullptr;
};

/// The neighbor search structure on the device (float coordinates, D = 2 or 3).
template <int D>
class grid {
    static_assert(D == 2 || D == 3, "frnn supports 2D and 3D points");

public:
    explicit grid(context& ctx);
    ~grid();
    grid(grid&&) noexcept;
    grid& operator=(grid&&) noexcept;

    /// Builds over N*D interleaved coordinates from the host, any finite radius: where r^2
    /// leaves float's range the coordinates are multiplied by the search scale on the host.
    /// A build that throws leaves the grid as it was (every check runs first); after
    /// std::bad_alloc, or a failure once the device has begun rebuilding, the grid is empty.
    void build(std::span<const float> coords, float radius, const grid_options& options = {});
    /// Builds over the caller's buffer: n*D interleaved floats, read in place (no copy). Radii
    /// that need a search scale (outside [2^-49, 2^63)) are refused with frnn::error.
    void build(buffer_view coords, std::size_t n, float radius, const grid_options& options = {});

    std::size_t size() const;
    float radius() const;             ///< the caller's radius
    /// The power of two s of frnn/search_scale.hpp (1 except for extreme radii): the device
    /// holds positions, radius and box times s, so shader_buffers() and the squared distances
    /// of neighbor_lists_on_device() are in those units. Host results are in the caller's.
    float search_scale() const;
    grid_kind kind() const;           ///< uniform or hashed, never automatic
    std::size_t slot_count() const;   ///< slots of the cell index: cells (uniform) or table size (hashed)
    /// Where the cells are (frnn/grid_geometry.hpp), chosen by the CPU grid's rules with cells
    /// as wide as asked (no margin). The device locates points in float, so a point within
    /// float rounding of a cell face (about 2^-23 of its cell coordinate) may sit in the cell
    /// beside the one cell_of() gives; it visits the cells that [x - r, x + r] touches, within
    /// cells_within(x). Its hashed table numbers slots with grid.glsl's own hash, not
    /// slot_of_cell().
    const grid_geometry<float>& geometry() const;

    /// sorted_to_original()[s]: the caller's index of the s-th point in cell order.
    std::vector<std::uint32_t> sorted_to_original() const;
    /// Number of neighbors of every point.
    std::vector<std::uint32_t> count_neighbors(index_space space = index_space::original) const;
    /// Neighbor lists of every point (all of list_options supported). Lists larger than one
    /// storage buffer (maxStorageBufferRange) are filled in chunks of rows.
    csr<float> neighbor_lists(const list_options& options = {}) const;
    /// At most k nearest neighbors within r of every point, sorted by distance (ties by index).
    csr<float> nearest(std::size_t k, const list_options& options = {}) const;

    /// Points of this grid within r of each query point (N_q*D interleaved host values): row q
    /// holds grid indices (`space` numbers them; `half` and `self` do not apply).
    csr<float> query(std::span<const float> queries, const list_options& options = {}) const;
    std::vector<std::uint32_t> query_counts(std::span<const float> queries) const;
    csr<float> query_nearest(std::span<const float> queries, std::size_t k,
                             const list_options& options = {}) const;

    /// Neighbor lists left on the device: uint32 offsets (rows + 1), uint32 indices and, when
    /// options.distances, float squared distances (in search units: times search_scale()^2). Owned by the grid, valid until its next
    /// query or build. All pairs must fit one storage buffer (frnn::error otherwise).
    struct device_csr {
        buffer_view offsets, indices, distances_squared;
        std::size_t rows = 0, pairs = 0;
    };
    device_csr neighbor_lists_on_device(const list_options& options = {});

    /// Buffers for frnn/grid.glsl, bindings 0-4: parameters, sorted positions, sorted cell
    /// coordinates, slot starts, sorted -> original map.
    std::array<buffer_view, 5> shader_buffers() const;
    /// Value for the specialization constant frnn_kind of frnn/grid.glsl (constant_id 0):
    /// 0 uniform, 1 hashed, 2 periodic. Optional: the default (3) reads it at run time.
    std::uint32_t shader_kind() const;

    context& owner() const;

private:
    std::unique_ptr<detail::grid_state> state_;
};

/// A user compute shader (SPIR-V) that includes frnn/grid.glsl. Set 0: bindings 0-4 are the
/// grid's buffers, bindings 5, 6, ... the caller's buffers in order; push constants up to
/// `push_bytes`. Dispatches of more than 65535 groups are split into rows: index invocations
/// with frnn_invocation_index() from grid.glsl. One pipeline per grid kind is created on first
/// use, specialized so the neighbor loop has no kind branches.
class kernel {
public:
    kernel(context& ctx, std::span<const std::uint32_t> spirv, std::size_t user_buffers,
           std::uint32_t push_bytes = 0);
    ~kernel();
    kernel(kernel&&) noexcept;
    kernel& operator=(kernel&&) noexcept;

    template <int D>
    void run(const grid<D>& g, std::span<const buffer_view> buffers, std::size_t groups,
             std::span<const std::byte> push = {}) const;

private:
    context* ctx_ = nullptr;
    std::size_t user_buffers_ = 0;
    std::uint32_t push_bytes_ = 0;
    std::vector<std::uint32_t> spirv_;
    mutable std::array<std::unique_ptr<detail::program>, 3> programs_;  // by grid kind
};

/// Convenience: neighbor lists of N*dim interleaved host coordinates (dim 2 or 3), computed on
/// the context's device. Same rows and pairs as frnn::grid<float, dim>::neighbor_lists.
csr<float> neighbor_lists(context& ctx, std::span<const float> coords, int dim, float radius,
                          const grid_options& grid = {}, const list_options& lists = {});
/// Same on a context of its own (first compute-capable device), created for this call.
csr<float> neighbor_lists(std::span<const float> coords, int dim, float radius,
                          const grid_options& grid = {}, const list_options& lists = {});
/// One call for a command-line tool or a benchmark: builds a grid over `coords` (N*dim
/// interleaved, dim 2 or 3) and returns, like the CPU grid, the neighbor lists of every point
/// (k == 0, no queries), their k nearest (k > 0), or the grid points around each query point
/// (`queries` non-empty, with k == 0 or k > 0), with the grid's kind, size and timings.
template <class T>
struct basic_search_result {
    csr<T> lists;
    grid_kind kind = grid_kind::uniform;  ///< the kind the grid chose
    std::size_t slots = 0;                ///< cell slots: the cells of a uniform grid, the table of a hashed one
    double build_ms = 0, query_ms = 0;    ///< wall time, including uploads and downloads
};
using search_result = basic_search_result<float>;
search_result search(context& ctx, std::span<const float> coords, int dim, float radius,
                     const grid_options& grid = {}, const list_options& lists = {},
                     std::span<const float> queries = {}, std::size_t k = 0);
/// The same for double input, answered in double: the device (float) finds candidates within
/// a radius widened by a bound on the rounding of the conversion to float, and the host keeps
/// those whose double distance, computed as frnn::grid<double, D> computes it, is <= radius.
/// So the pairs, distances and orders are those of the CPU grid in double. Lists are in the
/// caller's numbering (index_space::sorted is refused: a one-call search returns no cell
/// order). frnn::error naming the backend and the precision when the device cannot bound the
/// candidates: a coordinate beyond the float range, or a conversion error above the radius
/// (coordinates too large for this radius in float: about |x| > 2^21 r / sqrt(dim)).
basic_search_result<double> search(context& ctx, std::span<const double> coords, int dim, double radius,
                                   const grid_options& grid = {}, const list_options& lists = {},
                                   std::span<const double> queries = {}, std::size_t k = 0);

/// Neighbor counts of N*dim interleaved host coordinates, on the context's device.
std::vector<std::uint32_t> count_neighbors(context& ctx, std::span<const float> coords, int dim,
                                           float radius, const grid_options& grid = {});

extern template class grid<2>;
extern template class grid<3>;

}  // namespace frnn::vulkan
