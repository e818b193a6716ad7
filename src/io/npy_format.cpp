// Reading and writing the npy header: magic "\x93NUMPY", version, header length, then a
// Python dict literal {'descr': '<f8', 'fortran_order': False, 'shape': (N, 3), }.
#include "npy_format.hpp"

#include <bit>
#include <cstring>
#include <limits>

#include "frnn/io/read.hpp"
#include "util.hpp"

static_assert(std::endian::native == std::endian::little, "frnn io assumes a little-endian host");

namespace frnn::io {

namespace {
constexpr std::string_view magic = "\x93NUMPY";

// A cursor over the dictionary literal; errors name the byte offset in the file.
struct dict_parser {
    std::string_view text;
    std::size_t base;  // file offset of text[0]
    std::string_view name;
    std::size_t pos = 0;

    [[noreturn]] void bad(const std::string& what) const {
        detail::fail(name, "byte " + std::to_string(base + pos) + ": npy header: " + what);
    }
    void skip_space() {
        while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t' || text[pos] == '\n'))
            ++pos;
    }
    bool accept(char c) {
        skip_space();
        if (pos < text.size() && text[pos] == c) {
            ++pos;
            return true;
        }
        return false;
    }
    void expect(char c) {
        if (!accept(c)) bad(std::string("expected '") + c + "'");
    }
    std::string string_literal() {
        skip_space();
        if (pos >= text.size() || (text[pos] != '\'' && text[pos] != '"')) bad("expected a string");
        const char quote = text[pos++];
        const std::size_t end = text.find(quote, pos);
        if (end == std::string_view::npos) bad("unterminated string");
        std::string s(text.substr(pos, end - pos));
        pos = end + 1;
        return s;
    }
    bool boolean() {
        skip_space();
        for (auto [word, value] : {std::pair{std::string_view("True"), true}, {"False", false}})
            if (text.substr(pos, word.size()) == word) {
                pos += word.size();
                return value;
            }
        bad("expected True or False");
    }
    std::uint64_t integer() {
        skip_space();
        std::uint64_t v = 0;
        const auto r = std::from_chars(text.data() + pos, text.data() + text.size(), v);
        if (r.ec != std::errc()) bad("expected a non-negative integer in the shape");
        pos = std::size_t(r.ptr - text.data());
        if (pos < text.size() && text[pos] == 'L') ++pos;  // Python 2 long suffix
        return v;
    }
    std::vector<std::uint64_t> tuple() {
        expect('(');
        std::vector<std::uint64_t> shape;
        while (!accept(')')) {
            shape.push_back(integer());
            if (!accept(',')) {
                expect(')');
                break;
            }
        }
        return shape;
    }
};
}  // namespace

std::uint64_t npy_header::count() const {
    std::uint64_t n = 1;
    for (std::uint64_t s : shape) {
        if (s != 0 && n > std::numeric_limits<std::uint64_t>::max() / s)
            throw error("npy shape overflows 64-bit element count");
        n *= s;
    }
    return n;
}

npy_header parse_npy_header(std::string_view bytes, std::string_view name) {
    if (bytes.size() < 10 || bytes.substr(0, 6) != magic)
        detail::fail(name, "byte 0: not an npy file (missing the \\x93NUMPY magic)");
    const int major = static_cast<unsigned char>(bytes[6]);
    if (major < 1 || major > 3)
        detail::fail(name, "byte 6: unsupported npy format version " + std::to_string(major));
    std::size_t prefix = major == 1 ? 10 : 12, length = 0;
    if (bytes.size() < prefix) detail::fail(name, "byte 8: truncated npy header length");
    for (std::size_t k = prefix; k-- > 8;)
        length = length * 256 + static_cast<unsigned char>(bytes[k]);
    if (bytes.size() < prefix + length)
        detail::fail(name, "byte " + std::to_string(bytes.size()) + ": npy header truncated (" +
                               std::to_string(length) + " header bytes announced)");

    dict_parser p{bytes.substr(prefix, length), prefix, name};
    npy_header h;
    bool seen[3] = {false, false, false};
    p.expect('{');
    while (!p.accept('}')) {
        const std::size_t key_pos = p.pos;
        const std::string key = p.string_literal();
        p.expect(':');
        if (key == "descr") {
            h.descr = p.string_literal();
            seen[0] = true;
        } else if (key == "fortran_order") {
            h.fortran_order = p.boolean();
            seen[1] = true;
        } else if (key == "shape") {
            h.shape = p.tuple();
            seen[2] = true;
        } else {
            p.pos = key_pos;
            p.bad("unexpected key '" + key + "'");
        }
        if (!p.accept(',')) {
            p.expect('}');
            break;
        }
    }
    if (!seen[0] || !seen[1] || !seen[2])
        p.bad(std::string("missing key '") + (!seen[0] ? "descr" : !seen[1] ? "fortran_order" : "shape") +
              "'");
    h.data_offset = prefix + length;
    return h;
}

namespace detail {

std::string make_npy_header(std::string_view descr, std::span<const std::uint64_t> shape) {
    std::string dict = "{'descr': '" + std::string(descr) + "', 'fortran_order': False, 'shape': (";
    for (std::size_t k = 0; k < shape.size(); ++k) {
        if (k) dict += ", ";
        dict += std::to_string(shape[k]);
    }
    dict += shape.size() == 1 ? ",), }" : "), }";
    // numpy aligns the data to 64 bytes; the dict ends with spaces and one newline.
    const std::size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict += '\n';
    std::string out(magic);
    out += char(1);
    out += char(0);
    out += char(dict.size() & 0xff);
    out += char(dict.size() >> 8);
    if (dict.size() > 0xffff) throw error("npy header too long");
    return out + dict;
}

}  // namespace detail
}  // namespace frnn::io
