// .npy point reader: the header is parsed from the first bytes, then the data is read straight
// into the result (Fortran-order files are transposed on the way).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "frnn/io/read.hpp"
#include "util.hpp"

namespace frnn::io {

namespace {
using file_ptr = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

std::string shape_text(const std::vector<std::uint64_t>& shape) {
    std::string s = "(";
    for (std::size_t k = 0; k < shape.size(); ++k)
        s += (k ? ", " : "") + std::to_string(shape[k]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

/// Rows [begin, end) of the (n, d) array whose data starts at byte h.data_offset.
template <class T>
std::vector<T> read_rows(std::FILE* f, const npy_header& h, std::uint64_t begin, std::uint64_t end,
                         std::string_view name) {
    const std::uint64_t n = h.shape[0], d = h.shape[1], rows = end - begin;
    std::vector<T> values(rows * d);
    // C order: the rows lie together; Fortran order: all x, then all y, then all z.
    const std::uint64_t runs = h.fortran_order ? d : 1, run = h.fortran_order ? rows : rows * d;
    for (std::uint64_t a = 0; a < runs; ++a) {
        const std::uint64_t at = h.data_offset + (h.fortran_order ? a * n + begin : begin * d) * sizeof(T);
        if (std::fseek(f, long(at), SEEK_SET) != 0) detail::fail(name, "cannot seek to byte " + std::to_string(at));
        if (std::fread(values.data() + a * run, sizeof(T), run, f) != run)
            detail::fail(name, std::string("read error in the data: ") + std::strerror(errno));
    }
    if (!h.fortran_order) return values;
    std::vector<T> interleaved(values.size());
    for (std::uint64_t a = 0; a < d; ++a)
        for (std::uint64_t i = 0; i < rows; ++i) interleaved[i * d + a] = values[a * rows + i];
    return interleaved;
}
}  // namespace

point_set read_npy_points(const std::filesystem::path& file) { return read_npy_slice(file, 0, 1).points; }

namespace {
/// An opened .npy file of float32 or float64 data: its header and size.
struct npy_file {
    file_ptr f{nullptr, std::fclose};
    npy_header h;
    std::uint64_t size = 0;
    bool f32 = false;
};

npy_file open_npy(const std::filesystem::path& file, const std::string& name, const char* needs) {
    npy_file out;
    out.f = file_ptr(std::fopen(name.c_str(), "rb"), std::fclose);
    if (!out.f) detail::fail(name, std::string("cannot open: ") + std::strerror(errno));
    std::error_code ec;
    const std::uint64_t file_size = std::filesystem::file_size(file, ec);
    if (ec) detail::fail(name, "cannot read size: " + ec.message());
    out.size = file_size;

    // The header length sits in bytes 8-9 (version 1) or 8-11 (versions 2 and 3).
    std::string head(std::min<std::uint64_t>(file_size, 12), '\0');
    if (std::fread(head.data(), 1, head.size(), out.f.get()) != head.size())
        detail::fail(name, "read error in the header");
    std::size_t total = head.size();
    if (head.size() >= 10 && head.compare(0, 6, "\x93NUMPY") == 0) {
        const bool v1 = head[6] == 1;
        std::uint64_t length = std::uint8_t(head[8]) | std::uint64_t(std::uint8_t(head[9])) << 8;
        if (!v1 && head.size() == 12)
            length |= std::uint64_t(std::uint8_t(head[10])) << 16 |
                      std::uint64_t(std::uint8_t(head[11])) << 24;
        total = std::size_t(std::min<std::uint64_t>(file_size, (v1 ? 10 : 12) + length));
    }
    const std::size_t have = head.size();
    head.resize(std::max(total, have));
    if (total > have && std::fread(head.data() + have, 1, total - have, out.f.get()) != total - have)
        detail::fail(name, "read error in the header");
    out.h = parse_npy_header(head, name);
    const bool f32 = out.h.descr == "<f4", f64 = out.h.descr == "<f8";
    if (!f32 && !f64) {
        const bool big = !out.h.descr.empty() && out.h.descr[0] == '>';
        detail::fail(name, "dtype '" + out.h.descr + "' is not supported" + (big ? " (big-endian)" : "") + ": " + needs +
                               " need little-endian float32 ('<f4') or float64 ('<f8')");
    }
    out.f32 = f32;
    return out;
}

/// Fails unless the data of n rows of `width` values fills the file exactly.
void check_data_size(const npy_file& in, std::uint64_t n, std::uint64_t width, const std::string& name) {
    const npy_header& h = in.h;
    const std::uint64_t item = in.f32 ? 4 : 8;
    if (n > (std::uint64_t(1) << 60) / (item * 3))
        detail::fail(name, "shape " + shape_text(h.shape) + " is too large");
    const std::uint64_t need = n * width * item, avail = in.size - h.data_offset;
    if (avail < need)
        detail::fail(name, "byte " + std::to_string(in.size) + ": data truncated: shape " +
                               shape_text(h.shape) + " needs " + std::to_string(need) +
                               " bytes after the header (byte " + std::to_string(h.data_offset) +
                               "), the file has " + std::to_string(avail));
    if (avail > need)
        detail::fail(name, "byte " + std::to_string(h.data_offset + need) + ": " +
                               std::to_string(avail - need) +
                               " unexpected bytes after the data of shape " + shape_text(h.shape));
}
}  // namespace

point_slice read_npy_slice(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts) {
    const std::string name = file.string();
    npy_file in = open_npy(file, name, "point files");
    const npy_header& h = in.h;
    std::FILE* const f = in.f.get();
    const bool f32 = in.f32;
    if (h.shape.size() != 2 || (h.shape[1] != 2 && h.shape[1] != 3))
        detail::fail(name, "shape " + shape_text(h.shape) + " is not (N, 2) or (N, 3)");

    const std::uint64_t n = h.shape[0];
    check_data_size(in, n, h.shape[1], name);

    point_slice slice;
    slice.total = n;
    slice.first = slice_start(n, part, parts);
    const std::uint64_t end = slice_start(n, part + 1, parts);
    point_set& points = slice.points;
    points.dimension = int(h.shape[1]);
    if (f32)
        points.coords = read_rows<float>(f, h, slice.first, end, name);
    else
        points.coords = read_rows<double>(f, h, slice.first, end, name);
    std::visit([&](const auto& v) { detail::check_finite(std::span(v), points.dimension, name, slice.first); },
               points.coords);
    return slice;
}

std::vector<double> read_npy_values(const std::filesystem::path& file) {
    const std::string name = file.string();
    npy_file in = open_npy(file, name, "value files");
    npy_header h = in.h;
    if (!(h.shape.size() == 1 || (h.shape.size() == 2 && h.shape[1] == 1)))
        detail::fail(name, "shape " + shape_text(h.shape) + " is not (N,) or (N, 1)");
    const std::uint64_t n = h.shape[0];
    check_data_size(in, n, 1, name);
    h.shape = {n, 1};
    h.fortran_order = false;  // one column: both orders are the same bytes
    std::vector<double> out;
    if (in.f32) {
        const auto v = read_rows<float>(in.f.get(), h, 0, n, name);
        out.assign(v.begin(), v.end());
    } else {
        out = read_rows<double>(in.f.get(), h, 0, n, name);
    }
    return out;
}

}  // namespace frnn::io
