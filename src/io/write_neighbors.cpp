// The single-process neighbor writers: the frame of frnn/io/neighbor_file.hpp around member
// bodies encoded in blocks of rows, streamed to a temporary file. An .npz member's CRC is known
// only after its body, so its header is written with a zero CRC first and patched after it.
#include "frnn/io/write.hpp"

#include <vector>

#include "frnn/io/atomic_file.hpp"
#include "frnn/io/neighbor_file.hpp"
#include "util.hpp"

namespace frnn::io {

namespace {

/// Rows per encoded block: a few MB of output for dense lists.
constexpr std::size_t block_rows = 1 << 13;

template <class T>
void write_file(neighbor_format f, const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    if (needs_distances(f) && lists.distances.size() != lists.indices.size())
        detail::fail(file.string(), std::string(f == neighbor_format::pairs_csv ? "csv" : "npz") +
                                        " output needs neighbor lists with distances");
    const std::size_t rows = lists.rows();
    const std::uint64_t entries = f == neighbor_format::lists_npz ? lists.size() : count_pairs(lists, filter);
    const neighbor_frame unpatched = frame_of(f, file, rows, entries);
    output_file out(file);
    std::vector<std::uint32_t> crcs(std::size_t(member_count(f)), 0);
    std::string bytes;
    for (int m = 0; m < member_count(f); ++m) {
        const std::uint64_t start = out.position();
        out.write(unpatched.before[std::size_t(m)]);
        checksum body;
        std::size_t b = 0;
        do {  // at least one block: no rows still have an .npz offset
            const std::size_t e = std::min(rows, b + block_rows);
            encode_rows(bytes, f, m, lists, b, e, {}, filter, e == rows);
            if (f == neighbor_format::lists_npz) body = extended(body, bytes);
            out.write(bytes);
            b = e;
        } while (b < rows);
        // The member's CRC into its header right after its body: patching all three at the end
        // made the third member's writes about 8x slower on a 2-core test machine (262 MB: 530
        // against 70 ms, the time spent in the kernel's page cache copy).
        if (f == neighbor_format::lists_npz) {
            crcs[std::size_t(m)] = body.crc;
            const neighbor_frame frame = frame_of(f, file, rows, entries, crcs);
            out.patch(start, frame.before[std::size_t(m)].data(), frame.before[std::size_t(m)].size());
        }
    }
    out.write(frame_of(f, file, rows, entries, crcs).after);
    out.commit();
}

}  // namespace

bool is_neighbor_output(const std::filesystem::path& file) {
    const std::string ext = detail::lower_extension(file);
    return ext == ".npy" || ext == ".csv" || ext == ".npz";
}

template <class T>
void write_pairs_npy(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    write_file(neighbor_format::pairs_npy, file, lists, filter);
}

template <class T>
void write_pairs_csv(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    write_file(neighbor_format::pairs_csv, file, lists, filter);
}

template <class T>
void write_csr_npz(const std::filesystem::path& file, const csr<T>& lists) {
    write_file(neighbor_format::lists_npz, file, lists, pair_filter::all);
}

template <class T>
void write_neighbors(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    write_file(neighbor_format_of(file), file, lists, filter);
}

#define FRNN_IO_NEIGHBORS(T)                                                                  \
    template void write_pairs_npy(const std::filesystem::path&, const csr<T>&, pair_filter); \
    template void write_pairs_csv(const std::filesystem::path&, const csr<T>&, pair_filter); \
    template void write_csr_npz(const std::filesystem::path&, const csr<T>&);                \
    template void write_neighbors(const std::filesystem::path&, const csr<T>&, pair_filter);
FRNN_IO_NEIGHBORS(float)
FRNN_IO_NEIGHBORS(double)
#undef FRNN_IO_NEIGHBORS

}  // namespace frnn::io
