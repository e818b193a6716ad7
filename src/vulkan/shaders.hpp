// Internal: the SPIR-V of frnn's shaders, compiled by glslc at build time and embedded.
#pragma once
#include <cstdint>
#include <span>

namespace frnn::vulkan::detail {

enum class shader;

struct embedded_shader {
    std::span<const std::uint32_t> words;
    std::uint32_t bindings;  ///< storage buffers of set 0
    const char* name;
};

/// The shader compiled for dimension `dim` (2 or 3; ignored by dimension-free shaders).
embedded_shader embedded(shader s, int dim);

}  // namespace frnn::vulkan::detail
