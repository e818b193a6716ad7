// .ply point reader: the vertex element's x, y (and z when present) of any scalar type, in
// ascii, binary_little_endian or binary_big_endian files. Elements before the vertices are
// skipped item by item (list properties included); elements after them are not read. A binary
// file without lists before or in its vertices is also read in slices of rows (one per MPI rank).
#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "frnn/io/read.hpp"
#include "util.hpp"

namespace frnn::io {

namespace {
enum class scalar { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_scalar(std::string_view word, scalar& out) {
    static constexpr std::pair<std::string_view, scalar> names[] = {
        {"char", scalar::i8},    {"int8", scalar::i8},     {"uchar", scalar::u8},
        {"uint8", scalar::u8},   {"short", scalar::i16},   {"int16", scalar::i16},
        {"ushort", scalar::u16}, {"uint16", scalar::u16},  {"int", scalar::i32},
        {"int32", scalar::i32},  {"uint", scalar::u32},    {"uint32", scalar::u32},
        {"float", scalar::f32},  {"float32", scalar::f32}, {"double", scalar::f64},
        {"float64", scalar::f64}};
    for (auto [n, s] : names)
        if (n == word) {
            out = s;
            return true;
        }
    return false;
}

std::size_t size_of(scalar s) {
    static constexpr std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[int(s)];
}

/// Whether an ascii value fits an integer type (any value fits float and double).
bool fits(scalar s, double v) {
    static constexpr double lowest[] = {-128, 0, -32768, 0, -2147483648.0, 0};
    static constexpr double highest[] = {127, 255, 32767, 65535, 2147483647.0, 4294967295.0};
    if (s == scalar::f32 || s == scalar::f64) return true;
    return v == std::floor(v) && v >= lowest[int(s)] && v <= highest[int(s)];
}

std::string_view name_of(scalar s) {
    static constexpr std::string_view names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
    return names[int(s)];
}

struct property {
    std::string name;
    scalar type = scalar::f32;
    bool list = false;
    scalar count_type = scalar::u8;
};

struct element {
    std::string name;
    std::uint64_t count = 0;
    std::size_t header_line = 0;
    std::vector<property> props;
};

enum class encoding { ascii, little, big };

struct header {
    encoding format = encoding::ascii;
    std::vector<element> elements;
    std::size_t data_offset = 0;
    std::size_t lines = 0;  // header lines, so ascii data starts at line lines + 1
};

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t pos = 0;
    while ((pos = line.find_first_not_of(" \t\r", pos)) != std::string_view::npos) {
        const std::size_t end = line.find_first_of(" \t\r", pos);
        out.push_back(line.substr(pos, end - pos));
        pos = end;
    }
    return out;
}

header parse_header(std::string_view bytes, std::string_view name) {
    header h;
    bool format_seen = false;
    std::size_t pos = 0;
    while (true) {
        const std::size_t eol = bytes.find('\n', pos);
        ++h.lines;
        const auto where = "line " + std::to_string(h.lines) + ": ";
        if (eol == std::string_view::npos)
            detail::fail(name, where + (h.lines == 1 ? "not a ply file (empty)"
                                                     : "header ends without 'end_header'"));
        const auto w = words(bytes.substr(pos, eol - pos));
        pos = eol + 1;
        if (h.lines == 1) {
            if (w.size() != 1 || w[0] != "ply") detail::fail(name, where + "not a ply file (no 'ply' magic)");
            continue;
        }
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") break;
        if (w[0] == "format") {
            if (w.size() != 3) detail::fail(name, where + "expected 'format <type> 1.0'");
            if (w[1] == "ascii") h.format = encoding::ascii;
            else if (w[1] == "binary_little_endian") h.format = encoding::little;
            else if (w[1] == "binary_big_endian") h.format = encoding::big;
            else detail::fail(name, where + "unknown format '" + std::string(w[1]) + "'");
            format_seen = true;
        } else if (w[0] == "element") {
            double count;
            if (w.size() != 3 || !detail::parse_number(w[2], count) || count < 0 ||
                count != std::floor(count) || count > 4294967295.0)
                detail::fail(name, where + "expected 'element <name> <count>' with a count in [0, 2^32)");
            h.elements.push_back({std::string(w[1]), std::uint64_t(count), h.lines, {}});
        } else if (w[0] == "property") {
            if (h.elements.empty()) detail::fail(name, where + "property before any element");
            property p;
            const bool list = w.size() == 5 && w[1] == "list";
            if (!(list || w.size() == 3) ||
                (list && (!parse_scalar(w[2], p.count_type) || !parse_scalar(w[3], p.type))) ||
                (!list && !parse_scalar(w[1], p.type)))
                detail::fail(name, where + "expected 'property <type> <name>' or 'property list "
                                           "<count type> <type> <name>' with types such as "
                                           "uchar, int, float, double");
            if (list && (p.count_type == scalar::f32 || p.count_type == scalar::f64))
                detail::fail(name, where + "list count type must be an integer type");
            p.list = list;
            p.name = std::string(w.back());
            h.elements.back().props.push_back(p);
        } else {
            detail::fail(name, where + "unknown header keyword '" + std::string(w[0]) + "'");
        }
    }
    if (!format_seen) detail::fail(name, "line 2: missing 'format' line");
    h.data_offset = pos;
    return h;
}

// Binary data: scalars read at byte offsets, with bounds checks that name the item. `data` holds
// the file's bytes from `base` on (all of them, or a slice's rows); pos is a file offset.
struct binary_cursor {
    std::string_view data;
    std::uint64_t pos;
    bool swap;
    std::string_view name;
    std::uint64_t base = 0;

    double read(scalar s, const element& e, std::uint64_t item, const property& p) {
        const std::size_t n = size_of(s);
        const std::uint64_t end = base + data.size();
        if (end - pos < n)
            detail::fail(name, "byte " + std::to_string(end) + ": data truncated in element '" +
                                   e.name + "' item " + std::to_string(item) + " of " +
                                   std::to_string(e.count) + " (property '" + p.name + "')");
        unsigned char b[8];
        std::memcpy(b, data.data() + (pos - base), n);
        pos += n;
        if (swap) std::reverse(b, b + n);
        auto as = [&]<class U>(U) {
            U v;
            std::memcpy(&v, b, sizeof v);
            return double(v);
        };
        switch (s) {
            case scalar::i8: return as(std::int8_t{});
            case scalar::u8: return as(std::uint8_t{});
            case scalar::i16: return as(std::int16_t{});
            case scalar::u16: return as(std::uint16_t{});
            case scalar::i32: return as(std::int32_t{});
            case scalar::u32: return as(std::uint32_t{});
            case scalar::f32: return as(float{});
            case scalar::f64: return as(double{});
        }
        return 0;
    }
};

// Ascii data: white-space separated tokens; errors name the line.
struct ascii_cursor {
    std::string_view data;
    std::size_t pos;
    std::size_t line;
    std::string_view name;

    double read(scalar s, const element& e, std::uint64_t item, const property& p) {
        while (pos < data.size() && std::strchr(" \t\r\n", data[pos]) && data[pos] != '\0') {
            if (data[pos] == '\n') ++line;
            ++pos;
        }
        const std::string where = "line " + std::to_string(line) + ": element '" + e.name +
                                  "' item " + std::to_string(item) + " of " +
                                  std::to_string(e.count) + ", property '" + p.name + "': ";
        if (pos >= data.size()) detail::fail(name, where + "unexpected end of file");
        const std::size_t start = pos;
        while (pos < data.size() && !std::strchr(" \t\r\n", data[pos])) ++pos;
        const std::string_view token = data.substr(start, pos - start);
        double v;
        if (!detail::parse_number(token, v))
            detail::fail(name, where + "'" + std::string(token) + "' is not a number");
        if (!fits(s, v)) detail::fail(name, where + "'" + std::string(token) + "' is not a " + std::string(name_of(s)));
        return v;
    }
};

// Reads one item of element e; values of the scalar properties go to out (lists are skipped).
template <class Cursor>
void read_item(Cursor& c, const element& e, std::uint64_t item, double* out) {
    for (std::size_t k = 0; k < e.props.size(); ++k) {
        const property& p = e.props[k];
        if (!p.list) {
            out[k] = c.read(p.type, e, item, p);
            continue;
        }
        const double n = c.read(p.count_type, e, item, p);
        // Count types are integers, and ascii values fit their type: n converts exactly.
        if (n < 0 || n != std::floor(n))
            detail::fail(c.name, "element '" + e.name + "' item " + std::to_string(item) +
                                     ": bad list length " + std::to_string(n) + " of property '" +
                                     p.name + "'");
        for (std::uint64_t m = 0; m < std::uint64_t(n); ++m) c.read(p.type, e, item, p);
    }
}

/// Where the points are: the vertex element, its coordinate properties and their type.
struct vertex_layout {
    std::size_t vertex = 0;    ///< index of the element
    int axes[3] = {-1, -1, -1};  ///< property of x, y, z (-1: no z)
    int dimension = 3;
    bool all_float = true;     ///< every coordinate property is a float: read as float
};

vertex_layout layout_of(const header& h, std::string_view name) {
    vertex_layout l;
    while (l.vertex < h.elements.size() && h.elements[l.vertex].name != "vertex") ++l.vertex;
    if (l.vertex == h.elements.size()) detail::fail(name, "the header has no 'vertex' element");
    const element& v = h.elements[l.vertex];
    for (std::size_t k = 0; k < v.props.size(); ++k)
        for (int a = 0; a < 3; ++a)
            if (v.props[k].name == std::string_view(&"xyz"[a], 1)) {
                if (v.props[k].list)
                    detail::fail(name, "line " + std::to_string(v.header_line) + ": vertex property '" +
                                           v.props[k].name + "' is a list, expected a scalar");
                l.axes[a] = int(k);
                l.all_float = l.all_float && v.props[k].type == scalar::f32;
            }
    for (int a = 0; a < 2; ++a)
        if (l.axes[a] < 0)
            detail::fail(name, "line " + std::to_string(v.header_line) +
                                   ": element 'vertex' has no property '" + "xy"[a] + "'");
    l.dimension = l.axes[2] < 0 ? 2 : 3;
    return l;
}

/// The coordinates of vertices [first, end); the items of the elements before them are read
/// (and skipped) first when `from_start`, else the cursor already stands at vertex `first`.
template <class T, class Cursor>
std::vector<T> read_vertices(Cursor& c, const header& h, const vertex_layout& l, std::uint64_t first,
                             std::uint64_t end, bool from_start) {
    const std::size_t vertex = l.vertex;
    const int dimension = l.dimension;
    const auto& axes = l.axes;
    std::vector<double> values(64);
    for (std::size_t e = 0; e < vertex && from_start; ++e) {
        if (h.elements[e].props.empty()) continue;
        values.resize(std::max(values.size(), h.elements[e].props.size()));
        for (std::uint64_t item = 0; item < h.elements[e].count; ++item)
            read_item(c, h.elements[e], item, values.data());
    }
    const element& v = h.elements[vertex];
    values.resize(std::max(values.size(), v.props.size()));
    std::vector<T> coords;
    // A lying count must not allocate more than the file could hold.
    coords.reserve(std::min<std::size_t>(std::size_t(end - first) * std::size_t(dimension), c.data.size()));
    for (std::uint64_t item = first; item < end; ++item) {
        read_item(c, v, item, values.data());
        for (int a = 0; a < dimension; ++a) {
            const double x = values[std::size_t(axes[a])];
            if (!std::isfinite(x))
                detail::fail(c.name, "vertex " + std::to_string(item) +
                                         " has a non-finite coordinate (" + std::to_string(x) + ")");
            // An ascii value of a float property may lie beyond float's range.
            if (std::abs(x) > double(std::numeric_limits<T>::max())) {
                char text[32];
                std::snprintf(text, sizeof text, "%.9g", x);
                detail::fail(c.name, "vertex " + std::to_string(item) + " has a coordinate (" + text +
                                         ") beyond the range of its property's type");
            }
            coords.push_back(T(x));
        }
    }
    return coords;
}

/// Reads vertices [first, end) with `c`, as float or double as the layout says.
template <class Cursor>
point_set read_points_with(Cursor& c, const header& h, const vertex_layout& l, std::uint64_t first, std::uint64_t end,
                           bool from_start) {
    point_set points;
    points.dimension = l.dimension;
    if (l.all_float) points.coords = read_vertices<float>(c, h, l, first, end, from_start);
    else points.coords = read_vertices<double>(c, h, l, first, end, from_start);
    return points;
}

/// The bytes of one item of an element without lists; 0 when it has a list.
std::uint64_t record_size(const element& e) {
    std::uint64_t bytes = 0;
    for (const property& p : e.props) {
        if (p.list) return 0;
        bytes += size_of(p.type);
    }
    return bytes;
}
}  // namespace

point_set parse_ply_points(std::string_view bytes, std::string_view name) {
    const header h = parse_header(bytes, name);
    const vertex_layout l = layout_of(h, name);
    const std::uint64_t count = h.elements[l.vertex].count;
    if (h.format == encoding::ascii) {
        ascii_cursor c{bytes, h.data_offset, h.lines + 1, name};
        return read_points_with(c, h, l, 0, count, true);
    }
    binary_cursor c{bytes, h.data_offset, h.format == encoding::big, name};
    return read_points_with(c, h, l, 0, count, true);
}

std::optional<point_slice> read_ply_slice(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts) {
    const std::string name = file.string();
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(name.c_str(), "rb"), std::fclose);
    if (!f) detail::fail(name, std::string("cannot open: ") + std::strerror(errno));
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(file, ec);
    if (ec) detail::fail(name, "cannot read size: " + ec.message());
    // The header from the first 64 KiB; a longer one, or any problem with it, goes to the
    // whole-file reader, which names it exactly.
    std::string head(std::min<std::uint64_t>(size, 1 << 16), '\0');
    if (std::fread(head.data(), 1, head.size(), f.get()) != head.size()) detail::fail(name, "read error in the header");
    header h;
    vertex_layout l;
    try {
        h = parse_header(head, name);
        l = layout_of(h, name);
    } catch (const error&) {
        return std::nullopt;
    }
    // Slices need rows at fixed offsets: binary, and no list before or in the vertices.
    if (h.format == encoding::ascii) return std::nullopt;
    std::uint64_t at = h.data_offset;
    for (std::size_t e = 0; e < l.vertex; ++e) {
        const std::uint64_t bytes = record_size(h.elements[e]);
        if (bytes == 0 && !h.elements[e].props.empty()) return std::nullopt;
        at += bytes * h.elements[e].count;
    }
    const element& v = h.elements[l.vertex];
    const std::uint64_t record = record_size(v);
    if (record == 0 || at > size) return std::nullopt;  // the elements before end early: read whole

    point_slice slice;
    slice.total = v.count;
    slice.first = slice_start(v.count, part, parts);
    const std::uint64_t end = slice_start(v.count, part + 1, parts);
    const std::uint64_t from = at + slice.first * record, to = std::min(size, at + end * record);
    std::string rows(from < to ? to - from : 0, '\0');
    if (!rows.empty() && (::fseeko(f.get(), off_t(from), SEEK_SET) != 0 ||
                          std::fread(rows.data(), 1, rows.size(), f.get()) != rows.size()))
        detail::fail(name, "read error: the file changed or ended while being read");
    binary_cursor c{rows, from, h.format == encoding::big, name, from};
    slice.points = read_points_with(c, h, l, slice.first, end, false);
    return slice;
}

point_set read_ply_points(const std::filesystem::path& file) {
    return parse_ply_points(detail::read_file(file), file.string());
}

}  // namespace frnn::io
