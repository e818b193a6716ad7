// PNG writer and reader: 8-bit RGB, no row filter, the image data compressed by zlib (at its
// fastest level: rendered frames are mostly flat color, which even that packs tightly), a
// CRC-32 per chunk, as the PNG specification requires.
#include <zlib.h>

#include <cstring>

#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"

namespace frnn::sim {
namespace {

std::uint32_t chunk_crc(const char* p, std::size_t n) {
    return std::uint32_t(crc32_z(0, reinterpret_cast<const Bytef*>(p), n));
}

void put32(std::string& s, std::uint32_t v) {
    for (int k = 3; k >= 0; --k) s += char(v >> (8 * k) & 0xFF);
}
std::uint32_t get32(const std::string& s, std::size_t at) {
    if (at + 4 > s.size()) throw error("png: truncated at byte " + std::to_string(at));
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = v << 8 | std::uint8_t(s[at + std::size_t(k)]);
    return v;
}

void chunk(std::string& out, const char* type, const std::string& data) {
    put32(out, std::uint32_t(data.size()));
    std::string body = std::string(type, 4) + data;
    out += body;
    put32(out, chunk_crc(body.data(), body.size()));
}

}  // namespace

std::string encode_png(const image& img) {
    if (img.width <= 0 || img.height <= 0 || img.rgb.size() != std::size_t(img.width) * std::size_t(img.height) * 3)
        throw error("encode_png: image size does not match its pixels");
    // Raw scanlines, each with filter byte 0.
    std::string raw;
    const std::size_t row = std::size_t(img.width) * 3;
    raw.reserve((row + 1) * std::size_t(img.height));
    for (int y = 0; y < img.height; ++y) {
        raw += '\0';
        raw.append(reinterpret_cast<const char*>(img.rgb.data()) + std::size_t(y) * row, row);
    }
    uLongf packed = compressBound(uLong(raw.size()));
    std::string z(packed, '\0');
    if (compress2(reinterpret_cast<Bytef*>(z.data()), &packed, reinterpret_cast<const Bytef*>(raw.data()),
                  uLong(raw.size()), Z_BEST_SPEED) != Z_OK)
        throw error("encode_png: zlib could not compress the image");
    z.resize(packed);

    std::string out = "\x89PNG\r\n\x1a\n";
    std::string ihdr;
    put32(ihdr, std::uint32_t(img.width));
    put32(ihdr, std::uint32_t(img.height));
    ihdr += char(8);  // bit depth
    ihdr += char(2);  // truecolor RGB
    ihdr += std::string(3, '\0');
    chunk(out, "IHDR", ihdr);
    chunk(out, "IDAT", z);
    chunk(out, "IEND", "");
    return out;
}

image decode_png(const std::string& s) {
    if (s.size() < 8 || s.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) throw error("png: bad signature");
    image img;
    std::string z;
    for (std::size_t at = 8; at < s.size();) {
        const std::uint32_t len = get32(s, at);
        if (at + 12 + len > s.size()) throw error("png: chunk overruns the file at byte " + std::to_string(at));
        const std::string type = s.substr(at + 4, 4);
        const std::uint32_t crc = get32(s, at + 8 + len);
        if (crc != chunk_crc(s.data() + at + 4, 4 + len))
            throw error("png: CRC mismatch in chunk " + type);
        if (type == "IHDR") img.width = int(get32(s, at + 8)), img.height = int(get32(s, at + 12));
        if (type == "IDAT") z += s.substr(at + 8, len);
        at += 12 + len;
    }
    if (img.width <= 0 || img.height <= 0 || img.width > (1 << 16) || img.height > (1 << 16))
        throw error("png: image size " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                    " is not within 1 to 65536 pixels a side");
    const std::size_t row = std::size_t(img.width) * 3;
    std::string raw((row + 1) * std::size_t(img.height), '\0');
    uLongf size = uLongf(raw.size());
    if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(z.data()),
                   uLong(z.size())) != Z_OK ||
        size != raw.size())
        throw error("png: the image data is not a zlib stream of " + std::to_string(raw.size()) + " bytes");
    for (int y = 0; y < img.height; ++y)
        if (raw[std::size_t(y) * (row + 1)] != 0)
            throw error("png: row " + std::to_string(y) + " uses filter " +
                        std::to_string(int(std::uint8_t(raw[std::size_t(y) * (row + 1)]))) + "; only 0 is read");
    img.rgb.resize(row * std::size_t(img.height));
    for (int y = 0; y < img.height; ++y) std::memcpy(img.rgb.data() + std::size_t(y) * row, raw.data() + std::size_t(y) * (row + 1) + 1, row);
    return img;
}

}  // namespace frnn::sim
