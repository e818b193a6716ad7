// The bytes of the neighbor files: pair and list encodings of row blocks, and the frame around
// them (npy headers; for .npz the zip container: local headers, central directory, zlib's
// CRC-32). Zip members are stored uncompressed with a fixed date, so archives are identical
// from run to run.
#include "frnn/io/neighbor_file.hpp"

#include <zlib.h>

#include <charconv>
#include <cstring>

#include "npy_format.hpp"
#include "util.hpp"

namespace frnn::io {

namespace {

void put16(std::string& s, std::uint32_t v) {
    s += char(v & 0xff);
    s += char((v >> 8) & 0xff);
}
void put32(std::string& s, std::uint32_t v) {
    put16(s, v & 0xffff);
    put16(s, v >> 16);
}

// 1980-01-01 00:00.
constexpr std::uint32_t dos_time = 0, dos_date = (1 << 5) | 1;

constexpr const char* npz_names[3] = {"offsets.npy", "indices.npy", "distances.npy"};

/// A stored zip member: its name, CRC, size and the offset of its local header.
struct zip_member {
    std::string name;
    std::uint32_t crc = 0;
    std::uint64_t size = 0;
    std::uint64_t offset = 0;
};

std::string local_header(const zip_member& m) {
    std::string s;
    put32(s, 0x04034b50);
    put16(s, 20);  // version needed: 2.0
    put16(s, 0);   // flags
    put16(s, 0);   // method: stored
    put16(s, dos_time);
    put16(s, dos_date);
    put32(s, m.crc);
    put32(s, std::uint32_t(m.size));  // compressed size
    put32(s, std::uint32_t(m.size));  // uncompressed size
    put16(s, std::uint32_t(m.name.size()));
    put16(s, 0);  // extra field length
    return s + m.name;
}

std::string central_entry(const zip_member& m) {
    std::string s;
    put32(s, 0x02014b50);
    put16(s, 20);  // version made by
    put16(s, 20);  // version needed
    put16(s, 0);
    put16(s, 0);
    put16(s, dos_time);
    put16(s, dos_date);
    put32(s, m.crc);
    put32(s, std::uint32_t(m.size));
    put32(s, std::uint32_t(m.size));
    put16(s, std::uint32_t(m.name.size()));
    put16(s, 0);  // extra
    put16(s, 0);  // comment
    put16(s, 0);  // disk number
    put16(s, 0);  // internal attributes
    put32(s, 0);  // external attributes
    put32(s, std::uint32_t(m.offset));
    return s + m.name;
}

/// Writes v's bytes at p; returns the end.
template <class U>
char* put_value(char* p, U v) {
    std::memcpy(p, &v, sizeof(U));
    return p + sizeof(U);
}

/// Calls f(file_row, neighbor, entry) for the entries of rows [b, e) that `filter` keeps.
template <class T, class F>
void for_each_kept(const csr<T>& lists, std::size_t b, std::size_t e, std::uint64_t first_row, pair_filter filter, F&& f) {
    for (std::size_t i = b; i < e; ++i) {
        const std::uint64_t row = first_row + i;
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            if (filter == pair_filter::all || lists.indices[k] >= row) f(row, lists.indices[k], k);
    }
}

}  // namespace

neighbor_format neighbor_format_of(const std::filesystem::path& file) {
    const std::string ext = detail::lower_extension(file);
    if (ext == ".npy") return neighbor_format::pairs_npy;
    if (ext == ".csv") return neighbor_format::pairs_csv;
    if (ext == ".npz") return neighbor_format::lists_npz;
    detail::fail(file.string(), "unknown output extension '" + ext + "' (expected .npy, .csv or .npz)");
}

int member_count(neighbor_format f) { return f == neighbor_format::lists_npz ? 3 : 1; }

bool needs_distances(neighbor_format f) { return f != neighbor_format::pairs_npy; }

template <class T>
void encode_rows(std::string& s, neighbor_format f, int member, const csr<T>& lists, std::size_t b, std::size_t e,
                 row_numbering at, pair_filter filter, bool closes) {
    s.clear();  // keeps the capacity: the bytes of the last block are still in cache
    if (f == neighbor_format::pairs_npy) {
        s.resize(16 * (lists.offsets[e] - lists.offsets[b]));  // at most; cut to what is kept
        char* p = s.data();
        for_each_kept(lists, b, e, at.first_row, filter, [&](std::uint64_t i, std::uint32_t j, std::uint64_t) {
            p = put_value(put_value(p, std::int64_t(i)), std::int64_t(j));
        });
        s.resize(std::size_t(p - s.data()));
    } else if (f == neighbor_format::pairs_csv) {
        for_each_kept(lists, b, e, at.first_row, filter, [&](std::uint64_t i, std::uint32_t j, std::uint64_t k) {
            char line[96];
            char* p = std::to_chars(line, line + 20, i).ptr;
            *p++ = ',';
            p = std::to_chars(p, p + 20, j).ptr;
            *p++ = ',';
            p = std::to_chars(p, line + sizeof line - 1, lists.distances[k]).ptr;
            *p++ = '\n';
            s.append(line, p);
        });
    } else if (member == 0) {
        s.resize(8 * (e - b + (closes ? 1 : 0)));
        char* p = s.data();
        for (std::size_t i = b; i < e; ++i) p = put_value(p, std::int64_t(at.entries_before + lists.offsets[i]));
        if (closes) put_value(p, std::int64_t(at.entries_before + lists.offsets[e]));
    } else {
        s.resize(8 * (lists.offsets[e] - lists.offsets[b]));
        char* p = s.data();
        for (std::uint64_t k = lists.offsets[b]; k < lists.offsets[e]; ++k)
            p = member == 1 ? put_value(p, std::int64_t(lists.indices[k])) : put_value(p, double(lists.distances[k]));
    }
}

std::optional<std::uint64_t> encoded_size(neighbor_format f, int member, std::uint64_t rows, std::uint64_t entries,
                                          std::uint64_t kept, bool closes) {
    if (f == neighbor_format::pairs_npy) return 16 * kept;  // two int64 a pair
    if (f == neighbor_format::pairs_csv) return std::nullopt;
    return 8 * (member == 0 ? rows + (closes ? 1 : 0) : entries);  // one int64 or double a value
}

checksum checksum_of(std::string_view bytes) { return extended({}, bytes); }

checksum extended(checksum a, std::string_view bytes) {
    return {std::uint32_t(crc32_z(a.crc, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size())), a.bytes + bytes.size()};
}

checksum concatenate(checksum a, checksum b) {
    return {std::uint32_t(crc32_combine64(a.crc, b.crc, z_off64_t(b.bytes))), a.bytes + b.bytes};
}

neighbor_frame frame_of(neighbor_format f, const std::filesystem::path& file, std::uint64_t rows, std::uint64_t entries,
                        std::span<const std::uint32_t> body_crcs) {
    neighbor_frame frame;
    if (f == neighbor_format::pairs_csv) {
        frame.before = {"i,j,distance\n"};
        return frame;
    }
    if (f == neighbor_format::pairs_npy) {
        const std::uint64_t shape[2] = {entries, 2};
        frame.before = {detail::make_npy_header(detail::npy_descr<std::int64_t>(), shape)};
        return frame;
    }
    // .npz: each member is a local header, an npy header and the body (8 bytes a value).
    const std::uint64_t counts[3] = {rows + 1, entries, entries};
    const std::string_view descr[3] = {"<i8", "<i8", "<f8"};
    std::string npy_headers[3];
    zip_member members[3];
    std::uint64_t at = 0;
    for (int m = 0; m < 3; ++m) {
        const std::uint64_t shape[1] = {counts[m]};
        npy_headers[m] = detail::make_npy_header(descr[m], shape);
        const checksum body{body_crcs.empty() ? 0u : body_crcs[std::size_t(m)], 8 * counts[m]};
        const checksum whole = concatenate(checksum_of(npy_headers[m]), body);
        members[m] = {npz_names[m], whole.crc, whole.bytes, at};
        at += 30 + members[m].name.size() + whole.bytes;
    }
    std::string directory;
    for (const zip_member& m : members) directory += central_entry(m);
    if (at + directory.size() + 22 >= 0xffffffffu)
        detail::fail(file.string(), "npz archive would exceed 4 GiB (zip64 is not supported); write .npy or .csv instead");
    for (int m = 0; m < 3; ++m) frame.before.push_back(local_header(members[m]) + npy_headers[m]);
    frame.after = directory;
    put32(frame.after, 0x06054b50);
    put16(frame.after, 0);  // this disk
    put16(frame.after, 0);  // disk of the directory
    put16(frame.after, 3);  // entries on this disk
    put16(frame.after, 3);  // entries in total
    put32(frame.after, std::uint32_t(directory.size()));
    put32(frame.after, std::uint32_t(at));
    put16(frame.after, 0);  // comment length
    return frame;
}

template void encode_rows(std::string&, neighbor_format, int, const csr<float>&, std::size_t, std::size_t, row_numbering,
                          pair_filter, bool);
template void encode_rows(std::string&, neighbor_format, int, const csr<double>&, std::size_t, std::size_t, row_numbering,
                          pair_filter, bool);

}  // namespace frnn::io
