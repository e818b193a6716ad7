#include "vulkan_env.hpp"

#include <cstring>

namespace frnn::vulkan::test {

bool validation_layer_installed() {
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (const auto& l : layers)
        if (std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0) return true;
    return false;
}

context_options test_options() {
    context_options o;
    o.validation = validation_layer_installed();
    o.on_message = [](severity s, const std::string& m) { validation_messages().add(s, m); };
    return o;
}

context* shared_context(std::string* why) {
    static std::unique_ptr<context> ctx;
    static std::string failure;
    static bool tried = false;
    if (!tried) {
        tried = true;
        try {
            ctx = std::make_unique<context>(test_options());
        } catch (const frnn::error& e) {
            failure = e.what();
        }
    }
    if (why) *why = failure;
    return ctx.get();
}

}  // namespace frnn::vulkan::test
