// Internal: the Vulkan device behind a frnn::vulkan::context, its buffers, compute programs and
// the recording of one synchronous submission (dispatches separated by barriers).
#pragma once
#include <vulkan/vulkan.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "frnn/vulkan.hpp"

namespace frnn::vulkan::detail {

[[noreturn]] void fail_call(VkResult result, const char* call, const char* file, int line);

#define FRNN_VK(call)                                                                  \
    do {                                                                               \
        const VkResult frnn_vk_result_ = (call);                                       \
        if (frnn_vk_result_ != VK_SUCCESS)                                             \
            ::frnn::vulkan::detail::fail_call(frnn_vk_result_, #call, __FILE__, __LINE__); \
    } while (0)

/// A VkBuffer with its own memory. Storage buffers are checked against maxStorageBufferRange.
class buffer {
public:
    enum class kind { storage, staging };
    buffer() = default;
    buffer(device& dev, VkDeviceSize bytes, kind k, const std::string& what);
    ~buffer();
    buffer(buffer&& other) noexcept { *this = std::move(other); }
    buffer& operator=(buffer&& other) noexcept;

    VkBuffer handle() const { return handle_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }
    buffer_view view() const { return {handle_, 0, size_}; }
    buffer_view view(VkDeviceSize offset, VkDeviceSize bytes) const { return {handle_, offset, bytes}; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    void release();
    device* dev_ = nullptr;
    VkBuffer handle_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

/// Value of the grid-kind specialization constant of frnn/grid.glsl (constant_id 0).
enum class kind_constant : std::uint32_t { uniform = 0, hashed = 1, periodic = 2, runtime = 3 };

/// A compute pipeline whose set 0 holds `bindings` storage buffers, with the grid-kind
/// specialization constant set to `kind`.
class program {
public:
    program(device& dev, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
            std::uint32_t push_bytes, const char* name, kind_constant kind = kind_constant::runtime);
    ~program();
    program(const program&) = delete;
    program& operator=(const program&) = delete;

    std::uint32_t bindings() const { return bindings_; }
    std::uint32_t push_bytes() const { return push_bytes_; }
    VkPipeline pipeline() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    VkDescriptorSetLayout set_layout() const { return set_layout_; }
    const std::string& name() const { return name_; }

private:
    void release();
    device* dev_;
    std::uint32_t bindings_, push_bytes_;
    std::string name_;
    VkShaderModule module_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

/// The internal shaders, each compiled for 2D and 3D.
enum class shader { bbox, insert, scan_block, scan_add, scatter, stable, count, fill, knn, sort_rows };

class device {
public:
    explicit device(const context_options& options);
    explicit device(const external_device& ext);
    ~device();
    device(const device&) = delete;
    device& operator=(const device&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical() const { return physical_; }
    VkDevice handle() const { return device_; }
    VkQueue queue() const { return queue_; }
    std::uint32_t family() const { return family_; }
    const device_info& info() const { return info_; }
    const VkPhysicalDeviceProperties& properties() const { return props_; }
    std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags want,
                              VkMemoryPropertyFlags prefer) const;

    /// The internal program of a shader for dimension d and grid kind (created on first use).
    program& get(shader s, int dim, kind_constant kind = kind_constant::runtime);

    // Recording of one submission. begin() starts it; every command is followed by a global
    // barrier so the next one sees its writes; submit() waits for completion.
    void begin();
    void dispatch(const program& p, std::initializer_list<buffer_view> bindings, const void* push,
                  std::size_t push_bytes, std::size_t groups);
    void dispatch(const program& p, std::span<const buffer_view> bindings, const void* push,
                  std::size_t push_bytes, std::size_t groups);
    void fill(buffer_view dst, std::uint32_t value);
    void update(buffer_view dst, const void* data, std::size_t bytes);
    void copy(buffer_view src, buffer_view dst, VkDeviceSize bytes);
    void submit();

    // Host transfers through a staging buffer (each its own submission).
    void upload(buffer_view dst, const void* data, std::size_t bytes);
    void download(buffer_view src, void* data, std::size_t bytes);

private:
    void release();
    void init_device();
    void init_common();
    void barrier();
    void pick_physical(int index);

    bool owns_ = false;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t family_ = 0;
    device_info info_;
    VkPhysicalDeviceProperties props_{};
    VkPhysicalDeviceMemoryProperties mem_{};
    std::unique_ptr<message_callback> callback_;

    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptors_ = VK_NULL_HANDLE;
    bool recording_ = false;
    std::uint32_t max_groups_x_ = 65535;  // Vulkan guarantees 65535 groups per dimension
    std::uint64_t max_binding_bytes_ = 0;  // 0: the device's maxStorageBufferRange
    std::map<std::array<int, 3>, std::unique_ptr<program>> programs_;
};

}  // namespace frnn::vulkan::detail
