// PNG writer with stored deflate blocks (no compression, no zlib): CRC-32 per chunk, Adler-32
// over the image data, as the PNG and zlib specifications require.
#include <array>
#include <cstring>

#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"

namespace frnn::sim {
namespace {

std::uint32_t crc32(const std::uint8_t* p, std::size_t n, std::uint32_t crc = 0) {
    static const auto table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    crc = ~crc;
    for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
    return ~crc;
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
    put32(out, crc32(reinterpret_cast<const std::uint8_t*>(body.data()), body.size()));
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
    std::string z;
    z += char(0x78);
    z += char(0x01);
    std::size_t pos = 0;
    do {
        const std::size_t len = std::min<std::size_t>(65535, raw.size() - pos);
        const bool last = pos + len == raw.size();
        z += char(last ? 1 : 0);
        z += char(len & 0xFF);
        z += char(len >> 8);
        z += char(~len & 0xFF);
        z += char((~len >> 8) & 0xFF);
        z.append(raw, pos, len);
        pos += len;
    } while (pos < raw.size());
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    put32(z, b << 16 | a);

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
        if (crc != crc32(reinterpret_cast<const std::uint8_t*>(s.data() + at + 4), 4 + len))
            throw error("png: CRC mismatch in chunk " + type);
        if (type == "IHDR") img.width = int(get32(s, at + 8)), img.height = int(get32(s, at + 12));
        if (type == "IDAT") z += s.substr(at + 8, len);
        at += 12 + len;
    }
    std::string raw;
    std::size_t p = 2;
    for (bool last = false; !last;) {
        if (p + 5 > z.size()) throw error("png: truncated deflate stream");
        last = z[p] & 1;
        if ((z[p] >> 1 & 3) != 0) throw error("png: only stored deflate blocks are supported");
        const std::size_t len = std::uint8_t(z[p + 1]) | std::size_t(std::uint8_t(z[p + 2])) << 8;
        raw += z.substr(p + 5, len);
        p += 5 + len;
    }
    const std::size_t row = std::size_t(img.width) * 3;
    if (raw.size() != (row + 1) * std::size_t(img.height)) throw error("png: image data has the wrong size");
    img.rgb.resize(row * std::size_t(img.height));
    for (int y = 0; y < img.height; ++y) std::memcpy(img.rgb.data() + std::size_t(y) * row, raw.data() + std::size_t(y) * (row + 1) + 1, row);
    return img;
}

}  // namespace frnn::sim
