#include "crc32.hpp"

#include <array>

namespace frnn::io::detail {

namespace {
constexpr std::array<std::uint32_t, 256> make_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t n = 0; n < 256; ++n) {
        std::uint32_t c = n;
        for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        table[n] = c;
    }
    return table;
}
constexpr auto table = make_table();
}  // namespace

std::uint32_t crc32_update(std::uint32_t crc, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    crc = ~crc;
    for (std::size_t k = 0; k < bytes; ++k) crc = table[(crc ^ p[k]) & 0xff] ^ (crc >> 8);
    return ~crc;
}

}  // namespace frnn::io::detail
