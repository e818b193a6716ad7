// .npz writer: a zip archive of three .npy members, stored without compression, as numpy.load
// reads it. The zip container (local headers, central directory; zlib's CRC-32) is written here: each
// member is streamed once and its checksum patched into its local header afterwards.
// Archives are limited to 4 GiB (no zip64); larger results should go to .npy or .csv.
#include <zlib.h>

#include <string>
#include <vector>

#include "frnn/io/write.hpp"
#include "npy_format.hpp"
#include "frnn/io/atomic_file.hpp"
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

// A fixed date (1980-01-01 00:00) keeps archives bit-identical from run to run.
constexpr std::uint32_t dos_time = 0, dos_date = (1 << 5) | 1;

struct member {
    std::string name;
    std::string header;   // npy header
    std::uint64_t count;  // values (8 bytes each)
    std::uint64_t size() const { return header.size() + count * 8; }
    std::uint64_t offset = 0;  // of the local header
    std::uint32_t crc = 0;
};

// Writes values through a checksum: the body of one member.
class crc_sink {
public:
    explicit crc_sink(output_file& out) : out_(out) {}
    void write(const void* data, std::size_t bytes) {
        crc_ = std::uint32_t(crc32_z(crc_, static_cast<const Bytef*>(data), bytes));
        out_.write(data, bytes);
    }
    template <class U, class Source>
    void write_values(std::uint64_t count, Source&& at) {
        std::vector<U> block;
        block.reserve(1 << 14);
        for (std::uint64_t k = 0; k < count; ++k) {
            block.push_back(U(at(k)));
            if (block.size() == block.capacity() || k + 1 == count) {
                write(block.data(), block.size() * sizeof(U));
                block.clear();
            }
        }
    }
    std::uint32_t crc() const { return crc_; }

private:
    output_file& out_;
    std::uint32_t crc_ = 0;
};

std::string local_header(const member& m) {
    std::string s;
    put32(s, 0x04034b50);
    put16(s, 20);  // version needed: 2.0
    put16(s, 0);   // flags
    put16(s, 0);   // method: stored
    put16(s, dos_time);
    put16(s, dos_date);
    put32(s, m.crc);
    put32(s, std::uint32_t(m.size()));  // compressed size
    put32(s, std::uint32_t(m.size()));  // uncompressed size
    put16(s, std::uint32_t(m.name.size()));
    put16(s, 0);  // extra field length
    return s + m.name;
}

std::string central_entry(const member& m) {
    std::string s;
    put32(s, 0x02014b50);
    put16(s, 20);  // version made by
    put16(s, 20);  // version needed
    put16(s, 0);
    put16(s, 0);
    put16(s, dos_time);
    put16(s, dos_date);
    put32(s, m.crc);
    put32(s, std::uint32_t(m.size()));
    put32(s, std::uint32_t(m.size()));
    put16(s, std::uint32_t(m.name.size()));
    put16(s, 0);  // extra
    put16(s, 0);  // comment
    put16(s, 0);  // disk number
    put16(s, 0);  // internal attributes
    put32(s, 0);  // external attributes
    put32(s, std::uint32_t(m.offset));
    return s + m.name;
}
}  // namespace

template <class T>
void write_csr_npz(const std::filesystem::path& file, const csr<T>& lists) {
    if (lists.distances.size() != lists.indices.size())
        detail::fail(file.string(), "npz output needs neighbor lists with distances");
    auto make = [](std::string name, std::string_view descr, std::uint64_t count) {
        const std::uint64_t shape[1] = {count};
        return member{std::move(name), detail::make_npy_header(descr, shape), count};
    };
    member members[3] = {make("offsets.npy", "<i8", lists.offsets.size()),
                         make("indices.npy", "<i8", lists.indices.size()),
                         make("distances.npy", "<f8", lists.distances.size())};
    std::uint64_t total = 22;
    for (const member& m : members) total += 30 + 46 + 2 * m.name.size() + m.size();
    if (total >= 0xffffffffu)
        detail::fail(file.string(), "npz archive would exceed 4 GiB (zip64 is not supported); "
                                    "write .npy or .csv instead");

    output_file out(file);
    for (int a = 0; a < 3; ++a) {
        member& m = members[a];
        m.offset = out.position();
        out.write(local_header(m));
        crc_sink body(out);
        body.write(m.header.data(), m.header.size());
        if (a == 0)
            body.write_values<std::int64_t>(m.count, [&](std::uint64_t k) { return lists.offsets[k]; });
        else if (a == 1)
            body.write_values<std::int64_t>(m.count, [&](std::uint64_t k) { return lists.indices[k]; });
        else
            body.write_values<double>(m.count, [&](std::uint64_t k) { return lists.distances[k]; });
        m.crc = body.crc();
        std::string crc;
        put32(crc, m.crc);
        out.patch(m.offset + 14, crc.data(), crc.size());
    }
    const std::uint64_t directory = out.position();
    std::string tail;
    for (const member& m : members) tail += central_entry(m);
    const std::uint64_t directory_size = tail.size();
    put32(tail, 0x06054b50);
    put16(tail, 0);  // this disk
    put16(tail, 0);  // disk of the directory
    put16(tail, 3);  // entries on this disk
    put16(tail, 3);  // entries in total
    put32(tail, std::uint32_t(directory_size));
    put32(tail, std::uint32_t(directory));
    put16(tail, 0);  // comment length
    out.write(tail);
    out.commit();
}

template void write_csr_npz(const std::filesystem::path&, const csr<float>&);
template void write_csr_npz(const std::filesystem::path&, const csr<double>&);

}  // namespace frnn::io
