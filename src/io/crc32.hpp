// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), the checksum of zip archives.
#pragma once
#include <cstddef>
#include <cstdint>

namespace frnn::io::detail {

/// Continues `crc` (0 to start) over `bytes` bytes of data.
std::uint32_t crc32_update(std::uint32_t crc, const void* data, std::size_t bytes);

}  // namespace frnn::io::detail
