// The Vulkan device of a context: instance and device creation (or wrapping), memory, buffers,
// pipelines, and synchronous submissions.
#include "device.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "shaders.hpp"

namespace frnn::vulkan::detail {

namespace {

const char* result_name(VkResult r) {
    switch (r) {
        case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
        case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
        case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
        case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
        case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
        case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
        case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
        case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
        case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
        case VK_TIMEOUT: return "VK_TIMEOUT";
        default: return "VkResult error";
    }
}

constexpr VkDeviceSize min_buffer_bytes = 16;  // Vulkan forbids empty buffers

VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT sev,
                                                VkDebugUtilsMessageTypeFlagsEXT type,
                                                const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                void* user) {
    // The loader's general warnings (e.g. "layers added by VK_INSTANCE_LAYERS") are not
    // problems of the application; its general errors ("no drivers") are kept.
    if (type == VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT &&
        !(sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT))
        return VK_FALSE;
    auto* cb = static_cast<message_callback*>(user);
    severity s = severity::verbose;
    if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) s = severity::error;
    else if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) s = severity::warning;
    else if (sev & VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT) s = severity::info;
    if (cb && *cb) (*cb)(s, data && data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

bool has_layer(const char* name) {
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool has_instance_extension(const char* name) {
    std::uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> ext(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, ext.data());
    return std::any_of(ext.begin(), ext.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

// First queue family with compute support, or -1.
int compute_family(VkPhysicalDevice pd) {
    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> fam(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fam.data());
    for (std::uint32_t i = 0; i < n; ++i)
        if (fam[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return int(i);
    return -1;
}

}  // namespace

void fail_call(VkResult result, const char* call, const char* file, int line) {
    throw error(std::string("vulkan: ") + call + " failed with " + result_name(result) + " (" +
                std::to_string(int(result)) + ") at " + file + ":" + std::to_string(line));
}

// ---------------------------------------------------------------------------------------------
// buffer

buffer::buffer(device& dev, VkDeviceSize bytes, kind k, const std::string& what) : dev_(&dev) {
    bytes = std::max(bytes, min_buffer_bytes);
    if (k == kind::storage && bytes > dev.info().max_storage_buffer_range)
        throw error("vulkan: " + what + " needs " + std::to_string(bytes) +
                    " bytes, more than this device's maxStorageBufferRange of " +
                    std::to_string(dev.info().max_storage_buffer_range) + " bytes (" + dev.info().name +
                    "); use fewer points or pairs per call, or the CPU grid");
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (k == kind::storage) info.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    FRNN_VK(vkCreateBuffer(dev.handle(), &info, nullptr, &handle_));
    size_ = bytes;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev.handle(), handle_, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex =
        k == kind::storage
            ? dev.memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
            : dev.memory_type(req.memoryTypeBits,
                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                              VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    const VkResult r = vkAllocateMemory(dev.handle(), &alloc, nullptr, &memory_);
    if (r != VK_SUCCESS) {
        release();
        throw error("vulkan: cannot allocate " + std::to_string(req.size) + " bytes for " + what +
                    " (" + result_name(r) + ")");
    }
    try {
        FRNN_VK(vkBindBufferMemory(dev.handle(), handle_, memory_, 0));
        if (k == kind::staging)
            FRNN_VK(vkMapMemory(dev.handle(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    } catch (...) {
        release();
        throw;
    }
}

buffer::~buffer() { release(); }

buffer& buffer::operator=(buffer&& other) noexcept {
    if (this != &other) {
        release();
        dev_ = other.dev_;
        handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        size_ = std::exchange(other.size_, 0);
        mapped_ = std::exchange(other.mapped_, nullptr);
    }
    return *this;
}

void buffer::release() {
    if (!dev_) return;
    if (handle_) vkDestroyBuffer(dev_->handle(), handle_, nullptr);
    if (memory_) vkFreeMemory(dev_->handle(), memory_, nullptr);  // unmaps too
    handle_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

// ---------------------------------------------------------------------------------------------
// program

program::program(device& dev, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                 std::uint32_t push_bytes, const char* name, kind_constant kind)
    : dev_(&dev), bindings_(bindings), push_bytes_(push_bytes), name_(name) {
    const VkDevice d = dev.handle();
    if (push_bytes > dev.properties().limits.maxPushConstantsSize)
        throw error("vulkan: program " + name_ + " wants " + std::to_string(push_bytes) +
                    " bytes of push constants, the device allows " +
                    std::to_string(dev.properties().limits.maxPushConstantsSize));
    try {
        VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        mi.codeSize = spirv.size() * sizeof(std::uint32_t);
        mi.pCode = spirv.data();
        FRNN_VK(vkCreateShaderModule(d, &mi, nullptr, &module_));

        std::vector<VkDescriptorSetLayoutBinding> b(bindings);
        for (std::uint32_t i = 0; i < bindings; ++i)
            b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
        VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        li.bindingCount = bindings;
        li.pBindings = b.data();
        FRNN_VK(vkCreateDescriptorSetLayout(d, &li, nullptr, &set_layout_));

        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
        VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pl.setLayoutCount = 1;
        pl.pSetLayouts = &set_layout_;
        pl.pushConstantRangeCount = push_bytes ? 1 : 0;
        pl.pPushConstantRanges = &range;
        FRNN_VK(vkCreatePipelineLayout(d, &pl, nullptr, &layout_));

        // Shaders without the constant ignore it.
        const std::uint32_t kind_value = std::uint32_t(kind);
        const VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
        const VkSpecializationInfo spec{1, &entry, sizeof(kind_value), &kind_value};
        VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        ci.stage.module = module_;
        ci.stage.pName = "main";
        ci.stage.pSpecializationInfo = &spec;
        ci.layout = layout_;
        FRNN_VK(vkCreateComputePipelines(d, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_));
    } catch (...) {
        release();
        throw;
    }
}

program::~program() { release(); }

void program::release() {
    const VkDevice d = dev_->handle();
    if (pipeline_) vkDestroyPipeline(d, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(d, set_layout_, nullptr);
    if (module_) vkDestroyShaderModule(d, module_, nullptr);
    pipeline_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    set_layout_ = VK_NULL_HANDLE;
    module_ = VK_NULL_HANDLE;
}

// ---------------------------------------------------------------------------------------------
// device

device::device(const context_options& options) : owns_(true) {
    if (options.max_groups_per_row < 1 || options.max_groups_per_row > 65535)
        throw error("vulkan: context_options::max_groups_per_row must lie in [1, 65535], got " +
                    std::to_string(options.max_groups_per_row));
    max_groups_x_ = options.max_groups_per_row;
    max_binding_bytes_ = options.max_binding_bytes;
    std::vector<const char*> layers, extensions;
    if (options.validation) {
        if (!has_layer("VK_LAYER_KHRONOS_validation"))
            throw error("vulkan: validation requested but VK_LAYER_KHRONOS_validation is not "
                        "installed (Debian package vulkan-validationlayers)");
        layers.push_back("VK_LAYER_KHRONOS_validation");
    }
    const bool debug = options.on_message && has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debug) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "frnn";
    app.pEngineName = "frnn";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ii{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ii.pApplicationInfo = &app;
    ii.enabledLayerCount = std::uint32_t(layers.size());
    ii.ppEnabledLayerNames = layers.data();
    ii.enabledExtensionCount = std::uint32_t(extensions.size());
    ii.ppEnabledExtensionNames = extensions.data();
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    if (debug) {
        callback_ = std::make_unique<message_callback>(options.on_message);
        mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        mi.pfnUserCallback = on_debug_message;
        mi.pUserData = callback_.get();
        ii.pNext = &mi;  // also reports problems of instance creation itself
    }
    const VkResult r = vkCreateInstance(&ii, nullptr, &instance_);
    if (r != VK_SUCCESS)
        throw error(std::string("vulkan: no Vulkan driver could be loaded (vkCreateInstance: ") +
                    result_name(r) + "); install a Vulkan driver, e.g. mesa-vulkan-drivers");
    try {
        if (debug) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
            if (create) FRNN_VK(create(instance_, &mi, nullptr, &messenger_));
        }
        pick_physical(options.device_index);
        init_device();
        init_common();
    } catch (...) {
        release();
        throw;
    }
}

device::device(const external_device& ext) : owns_(false) {
    if (!ext.instance || !ext.physical_device || !ext.device || !ext.queue)
        throw error("vulkan: external_device needs instance, physical_device, device and queue");
    instance_ = ext.instance;
    physical_ = ext.physical_device;
    device_ = ext.device;
    queue_ = ext.queue;
    family_ = ext.queue_family;
    std::uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, nullptr);
    std::vector<VkQueueFamilyProperties> fam(families);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, fam.data());
    if (family_ >= families || !(fam[family_].queueFlags & VK_QUEUE_COMPUTE_BIT))
        throw error("vulkan: external_device: queue family " + std::to_string(family_) +
                    " does not exist or has no compute support");
    init_common();
}

void device::pick_physical(int index) {
    std::uint32_t n = 0;
    FRNN_VK(vkEnumeratePhysicalDevices(instance_, &n, nullptr));
    std::vector<VkPhysicalDevice> pds(n);
    FRNN_VK(vkEnumeratePhysicalDevices(instance_, &n, pds.data()));
    if (n == 0) throw error("vulkan: no Vulkan device found (is a driver such as mesa-vulkan-drivers installed?)");
    if (index >= 0) {
        if (index >= int(n))
            throw error("vulkan: device index " + std::to_string(index) + " requested, " +
                        std::to_string(n) + " devices present");
        if (compute_family(pds[index]) < 0)
            throw error("vulkan: device " + std::to_string(index) + " has no compute queue");
        physical_ = pds[index];
    } else {
        for (auto pd : pds)
            if (compute_family(pd) >= 0) {
                physical_ = pd;
                break;
            }
        if (!physical_) throw error("vulkan: no Vulkan device with a compute queue");
    }
    family_ = std::uint32_t(compute_family(physical_));
}

void device::init_device() {
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family_;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    FRNN_VK(vkCreateDevice(physical_, &di, nullptr, &device_));
    vkGetDeviceQueue(device_, family_, 0, &queue_);
}

void device::init_common() {
    vkGetPhysicalDeviceProperties(physical_, &props_);
    vkGetPhysicalDeviceMemoryProperties(physical_, &mem_);
    info_.name = props_.deviceName;
    info_.api_version = props_.apiVersion;
    info_.max_storage_buffer_range = props_.limits.maxStorageBufferRange;
    if (max_binding_bytes_ > 0)
        info_.max_storage_buffer_range = std::min<std::uint64_t>(info_.max_storage_buffer_range, max_binding_bytes_);
    info_.is_cpu = props_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    // The shaders are SPIR-V 1.3, which needs Vulkan 1.1.
    if (props_.apiVersion < VK_API_VERSION_1_1)
        throw error("vulkan: " + info_.name + " supports Vulkan " + std::to_string(VK_API_VERSION_MAJOR(props_.apiVersion)) +
                    "." + std::to_string(VK_API_VERSION_MINOR(props_.apiVersion)) + ", frnn needs 1.1");
    // Only on our own instance, which is 1.1: a caller's instance may be 1.0.
    if (owns_) {
        VkPhysicalDeviceSubgroupProperties sub{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        p2.pNext = &sub;
        vkGetPhysicalDeviceProperties2(physical_, &p2);
        info_.subgroup_size = sub.subgroupSize;
    }

    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = family_;
    FRNN_VK(vkCreateCommandPool(device_, &pi, nullptr, &pool_));
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    FRNN_VK(vkAllocateCommandBuffers(device_, &ai, &cmd_));
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    FRNN_VK(vkCreateFence(device_, &fi, nullptr, &fence_));
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 4096};
    VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dp.maxSets = 256;
    dp.poolSizeCount = 1;
    dp.pPoolSizes = &size;
    FRNN_VK(vkCreateDescriptorPool(device_, &dp, nullptr, &descriptors_));
}

device::~device() { release(); }

void device::release() {
    if (device_) {
        if (recording_) {
            vkEndCommandBuffer(cmd_);
            recording_ = false;
        }
        programs_.clear();
        if (descriptors_) vkDestroyDescriptorPool(device_, descriptors_, nullptr);
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
        descriptors_ = VK_NULL_HANDLE;
        fence_ = VK_NULL_HANDLE;
        pool_ = VK_NULL_HANDLE;
    }
    if (owns_) {
        if (device_) vkDestroyDevice(device_, nullptr);
        if (messenger_) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy) destroy(instance_, messenger_, nullptr);
        }
        if (instance_) vkDestroyInstance(instance_, nullptr);
    }
    device_ = VK_NULL_HANDLE;
    messenger_ = VK_NULL_HANDLE;
    instance_ = VK_NULL_HANDLE;
}

std::uint32_t device::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags want,
                                  VkMemoryPropertyFlags prefer) const {
    int fallback = -1;
    for (std::uint32_t i = 0; i < mem_.memoryTypeCount; ++i) {
        if (!(type_bits & (1u << i))) continue;
        const auto flags = mem_.memoryTypes[i].propertyFlags;
        if ((flags & want) != want) continue;
        if ((flags & prefer) == prefer) return i;
        if (fallback < 0) fallback = int(i);
    }
    if (fallback < 0) throw error("vulkan: no suitable memory type on " + info_.name);
    return std::uint32_t(fallback);
}

program& device::get(shader s, int dim, kind_constant kind) {
    auto& slot = programs_[{int(s), dim, int(kind)}];
    if (!slot) {
        const embedded_shader e = embedded(s, dim);
        slot = std::make_unique<program>(*this, e.words, e.bindings, 32, e.name, kind);
    }
    return *slot;
}

void device::begin() {
    // A recording abandoned by an exception is dropped (never submitted).
    if (recording_) {
        vkEndCommandBuffer(cmd_);
        recording_ = false;
    }
    FRNN_VK(vkResetDescriptorPool(device_, descriptors_, 0));
    FRNN_VK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    FRNN_VK(vkBeginCommandBuffer(cmd_, &bi));
    recording_ = true;
}

// One global barrier after each command: compute and transfer writes become visible to the
// next compute or transfer command (and to the host at the end of the submission).
void device::barrier() {
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                       VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &mb, 0, nullptr, 0, nullptr);
}

void device::dispatch(const program& p, std::initializer_list<buffer_view> bindings,
                      const void* push, std::size_t push_bytes, std::size_t groups) {
    dispatch(p, std::span<const buffer_view>(bindings.begin(), bindings.size()), push, push_bytes,
             groups);
}

void device::dispatch(const program& p, std::span<const buffer_view> bindings, const void* push,
                      std::size_t push_bytes, std::size_t groups) {
    if (!recording_) throw error("vulkan: internal error: dispatch outside a submission");
    if (bindings.size() != p.bindings())
        throw error("vulkan: program " + p.name() + " takes " + std::to_string(p.bindings()) +
                    " buffers, " + std::to_string(bindings.size()) + " given");
    if (groups == 0) return;
    const std::size_t gx = std::min<std::size_t>(groups, max_groups_x_);
    const std::size_t gy = (groups + gx - 1) / gx;
    if (gy > props_.limits.maxComputeWorkGroupCount[1])
        throw error("vulkan: dispatch of " + std::to_string(groups) + " groups is too large");

    VkDescriptorSetLayout layout = p.set_layout();
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = descriptors_;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &layout;
    VkDescriptorSet set;
    FRNN_VK(vkAllocateDescriptorSets(device_, &ai, &set));
    std::vector<VkDescriptorBufferInfo> infos(bindings.size());
    std::vector<VkWriteDescriptorSet> writes(bindings.size());
    for (std::size_t i = 0; i < bindings.size(); ++i) {
        if (!bindings[i].buffer)
            throw error("vulkan: program " + p.name() + ": buffer " + std::to_string(i) + " is null");
        if (bindings[i].size > info_.max_storage_buffer_range)
            throw error("vulkan: program " + p.name() + ": binding " + std::to_string(i) + " of " +
                        std::to_string(bindings[i].size) +
                        " bytes exceeds maxStorageBufferRange (" +
                        std::to_string(info_.max_storage_buffer_range) + ")");
        infos[i] = {bindings[i].buffer, bindings[i].offset, bindings[i].size};
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = set;
        writes[i].dstBinding = std::uint32_t(i);
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(device_, std::uint32_t(writes.size()), writes.data(), 0, nullptr);
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline());
    vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    if (p.push_bytes()) {
        // Always push the whole declared range so no push constant is left undefined.
        std::vector<std::byte> bytes(p.push_bytes());
        if (push_bytes > bytes.size())
            throw error("vulkan: program " + p.name() + ": too many push-constant bytes");
        if (push_bytes) std::memcpy(bytes.data(), push, push_bytes);
        vkCmdPushConstants(cmd_, p.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           std::uint32_t(bytes.size()), bytes.data());
    }
    vkCmdDispatch(cmd_, std::uint32_t(gx), std::uint32_t(gy), 1);
    barrier();
}

void device::fill(buffer_view dst, std::uint32_t value) {
    vkCmdFillBuffer(cmd_, dst.buffer, dst.offset, dst.size, value);
    barrier();
}

void device::update(buffer_view dst, const void* data, std::size_t bytes) {
    vkCmdUpdateBuffer(cmd_, dst.buffer, dst.offset, bytes, data);
    barrier();
}

void device::copy(buffer_view src, buffer_view dst, VkDeviceSize bytes) {
    if (bytes == 0) return;
    VkBufferCopy region{src.offset, dst.offset, bytes};
    vkCmdCopyBuffer(cmd_, src.buffer, dst.buffer, 1, &region);
    barrier();
}

void device::submit() {
    if (!recording_) throw error("vulkan: internal error: submit without begin");
    recording_ = false;
    FRNN_VK(vkEndCommandBuffer(cmd_));
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    FRNN_VK(vkResetFences(device_, 1, &fence_));
    FRNN_VK(vkQueueSubmit(queue_, 1, &si, fence_));
    FRNN_VK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
}

void device::upload(buffer_view dst, const void* data, std::size_t bytes) {
    if (bytes == 0) return;
    buffer staging(*this, bytes, buffer::kind::staging, "upload staging buffer");
    std::memcpy(staging.mapped(), data, bytes);
    begin();
    copy(staging.view(), dst, bytes);
    submit();
}

void device::download(buffer_view src, void* data, std::size_t bytes) {
    if (bytes == 0) return;
    buffer staging(*this, bytes, buffer::kind::staging, "download staging buffer");
    begin();
    copy(src, staging.view(), bytes);
    submit();
    std::memcpy(data, staging.mapped(), bytes);
}

}  // namespace frnn::vulkan::detail
