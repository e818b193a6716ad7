// VTK XML output: PolyData frames, written by one process or by every rank, and the .pvd series.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "frnn/io/atomic_file.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"
#include "frnn/sim/ranks.hpp"

namespace frnn::sim {

namespace {

/// The frame's arrays, in file order: VTK type, name, components, bytes per particle.
struct vtp_array {
    const char* type;
    const char* name;
    int components;
    std::size_t bytes;
};
constexpr vtp_array arrays[] = {{"Float32", "velocity", 3, 12},  {"Float32", "speed", 1, 4}, {"Float32", "density", 1, 4},
                                {"Float32", "pressure", 1, 4},   {"UInt32", "id", 1, 4},     {"Float32", "Points", 3, 12},
                                {"Int32", "connectivity", 1, 4}, {"Int32", "offsets", 1, 4}};
constexpr std::size_t array_count = sizeof arrays / sizeof arrays[0];

/// The text before array k of a frame of n particles (k = array_count: the text after the last).
std::string text_before(std::size_t k, std::size_t n) {
    std::string t;
    if (k == 0)
        t = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\" "
            "header_type=\"UInt32\">\n  <PolyData>\n    <Piece NumberOfPoints=\"" +
            std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
            "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n      <PointData Scalars=\"speed\" "
            "Vectors=\"velocity\">\n";
    else
        t = "\n        </DataArray>\n";
    if (k == 5) t += "      </PointData>\n      <Points>\n";
    if (k == 6) t += "      </Points>\n      <Verts>\n";
    if (k == array_count) return t + "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    return t + "        <DataArray type=\"" + arrays[k].type + "\" Name=\"" + arrays[k].name + "\" NumberOfComponents=\"" +
           std::to_string(arrays[k].components) + "\" format=\"binary\">\n          ";
}

// Each array is VTK's "binary" inline format: base64 of a UInt32 byte count followed by the raw
// bytes, one stream of 4 + bytes n. A part of the particles (the ids [first, first + count) of
// the frame's n) holds the stream's bytes from start() on and writes the base64 groups (3 bytes,
// 4 characters) that begin among them, so that the parts' texts follow one another.

/// Base64 groups that begin before byte `offset` of a stream.
std::uint64_t groups_before(std::uint64_t offset) { return (offset + 2) / 3; }

/// The base64 of the groups beginning in `raw` (the stream's bytes from `start` on), taking the
/// bytes its last group lacks from `after` (the stream's next bytes), or padding it when `last`.
void encode_part(std::string& out, std::string_view raw, std::uint64_t start, std::string_view after, bool last) {
    static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const std::size_t skip = std::size_t(groups_before(start) * 3 - start);  // the previous part's last group
    if (skip >= raw.size()) return;
    std::string bytes(raw.substr(skip));
    if (const std::size_t tail = bytes.size() % 3; tail && !last) {
        if (after.size() < 3 - tail) throw error("write_vtp: a frame's part lacks the bytes after it");
        bytes.append(after.substr(0, 3 - tail));
    }
    const auto at = [&](std::size_t i) { return std::uint32_t(std::uint8_t(bytes[i])); };
    out.reserve(out.size() + bytes.size() * 4 / 3 + 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const std::uint32_t v = at(i) << 16 | at(i + 1) << 8 | at(i + 2);
        out += tbl[v >> 18 & 63], out += tbl[v >> 12 & 63], out += tbl[v >> 6 & 63], out += tbl[v & 63];
    }
    if (i < bytes.size()) {  // the stream's end
        std::uint32_t v = at(i) << 16;
        if (i + 1 < bytes.size()) v |= at(i + 1) << 8;
        out += tbl[v >> 18 & 63], out += tbl[v >> 12 & 63];
        out += i + 1 < bytes.size() ? tbl[v >> 6 & 63] : '=';
        out += '=';
    }
}

/// The particles with ids [first, first + p.n) of a frame of `total`, given in any order: raw[k]
/// holds their bytes of array k's stream, from start(k) on (the first part begins with the count).
struct frame_part {
    std::size_t first = 0, total = 0;
    std::string raw[array_count];
    std::uint64_t start(std::size_t k) const { return first == 0 ? 0 : 4 + arrays[k].bytes * first; }
};

frame_part make_part(const particle_view& p, std::size_t first, std::size_t total) {
    const std::size_t n = p.n;
    std::vector<float> pos(n * 3, 0.f), vel(n * 3, 0.f), speed(n), rho(n), pr(n);
    std::vector<std::uint32_t> ids(n);
    std::vector<std::int32_t> conn(n), offs(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (p.id[i] < first || p.id[i] - first >= n)
            throw error("write_vtp: particle id " + std::to_string(p.id[i]) + " out of range");
        const std::size_t k = p.id[i] - first;
        double s2 = 0;
        for (int a = 0; a < p.dim; ++a) {
            pos[k * 3 + a] = p.x[i * std::size_t(p.dim) + a];
            vel[k * 3 + a] = p.v[i * std::size_t(p.dim) + a];
            s2 += double(vel[k * 3 + a]) * vel[k * 3 + a];
        }
        speed[k] = float(std::sqrt(s2));
        rho[k] = p.rho[i];
        pr[k] = p.p[i];
        ids[k] = std::uint32_t(first + k);
    }
    for (std::size_t k = 0; k < n; ++k) conn[k] = std::int32_t(first + k), offs[k] = std::int32_t(first + k + 1);
    frame_part part;
    part.first = first, part.total = total;
    const void* data[array_count] = {vel.data(), speed.data(), rho.data(), pr.data(), ids.data(), pos.data(), conn.data(), offs.data()};
    for (std::size_t k = 0; k < array_count; ++k) {
        if (first == 0) {
            const std::uint32_t count = std::uint32_t(arrays[k].bytes * total);
            part.raw[k].assign(reinterpret_cast<const char*>(&count), sizeof count);
        }
        part.raw[k].append(static_cast<const char*>(data[k]), arrays[k].bytes * n);
    }
    return part;
}

/// Where array k's base64 begins in a frame of `total` particles (k = array_count: the
/// trailing text).
std::uint64_t array_offset(std::size_t k, std::size_t total) {
    std::uint64_t at = 0;
    for (std::size_t j = 0; j < k; ++j) at += text_before(j, total).size() + 4 * groups_before(4 + arrays[j].bytes * total);
    return at + text_before(k, total).size();
}

/// Writes `bytes` at `offset` of the open file fd; false on failure (errno set).
bool write_at(int fd, const std::string& bytes, std::uint64_t offset) {
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t w = ::pwrite(fd, bytes.data() + done, bytes.size() - done, off_t(offset + done));
        if (w <= 0) return false;
        done += std::size_t(w);
    }
    return true;
}

/// Every rank's `failure` ("" for none) on every rank; throws the first one there is, on all.
void agree(rank_comm& ranks, const std::string& failure) {
    for (const rank_bytes& b : ranks.all_gather(rank_bytes(failure.begin(), failure.end())))
        if (!b.empty()) throw ranks_agree_error(std::string(b.begin(), b.end()));
}

}  // namespace

void write_vtp(const std::string& path, const particle_view& p) {
    const frame_part part = make_part(p, 0, p.n);
    std::string out;
    for (std::size_t k = 0; k < array_count; ++k) {
        out += text_before(k, p.n);
        encode_part(out, part.raw[k], 0, {}, true);
    }
    out += text_before(array_count, p.n);
    io::write_file_atomically(path, out);
}

void write_vtp(const std::string& path, const particle_view& p, rank_comm& ranks) {
    const std::size_t me = std::size_t(ranks.rank()), count = std::size_t(ranks.size());
    // The ranks' particle counts: every rank checks every rank's share of the ids.
    const std::uint64_t n = p.n;
    std::vector<std::uint64_t> counts;
    for (const rank_bytes& b : ranks.all_gather(rank_bytes(reinterpret_cast<const char*>(&n), reinterpret_cast<const char*>(&n + 1)))) {
        std::uint64_t k = 0;
        if (b.size() == sizeof k) std::memcpy(&k, b.data(), sizeof k);
        counts.push_back(k);
    }
    std::size_t total = 0;
    for (std::uint64_t k : counts) total += std::size_t(k);
    std::size_t first = 0, mine = 0;
    for (std::size_t q = 0, at = 0; q < count; at += std::size_t(counts[q]), ++q) {
        if (at != total * q / count || at + counts[q] != total * (q + 1) / count)
            throw ranks_agree_error("write_vtp: rank " + std::to_string(q) + " holds " + std::to_string(counts[q]) +
                                    " particles from id " + std::to_string(at) + ", not its share of " + std::to_string(total));
        if (q == me) first = at, mine = std::size_t(counts[q]);
    }
    const frame_part part = make_part(p, first, total);
    // The first two bytes of each of this rank's streams: the ranks before it need them to end
    // their last groups. The part after which no rank holds particles pads its groups.
    rank_bytes heads;
    for (std::size_t k = 0; k < array_count && mine > 0; ++k) heads.insert(heads.end(), part.raw[k].end() - std::ptrdiff_t(arrays[k].bytes * mine), part.raw[k].end() - std::ptrdiff_t(arrays[k].bytes * mine) + 2);
    const std::vector<rank_bytes> all_heads = ranks.all_gather(heads);
    std::size_t next = me + 1;
    while (next < count && all_heads[next].empty()) ++next;
    const bool last = next == count;
    std::string pieces[array_count];
    for (std::size_t k = 0; k < array_count; ++k) {
        const std::string_view after = last ? std::string_view() : std::string_view(all_heads[next].data() + 2 * k, 2);
        encode_part(pieces[k], part.raw[k], part.start(k), after, last);
    }
    // Rank 0 makes the temporary file, every rank writes its pieces into it, rank 0 renames it.
    std::string failure, temp;
    if (me == 0) {
        temp = io::temporary_path_beside(path).string();
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd < 0 || ::ftruncate(fd, off_t(array_offset(array_count, total))) != 0)
            failure = path + ": cannot create temporary file " + temp + ": " + std::strerror(errno);
        if (fd >= 0) ::close(fd);
        if (!failure.empty()) ::unlink(temp.c_str());
    }
    const std::vector<rank_bytes> names = ranks.all_gather(failure.empty() ? rank_bytes(temp.begin(), temp.end()) : rank_bytes());
    agree(ranks, failure);
    temp.assign(names[0].begin(), names[0].end());
    const int fd = ::open(temp.c_str(), O_WRONLY);
    bool ok = fd >= 0;
    for (std::size_t k = 0; ok && k < array_count; ++k) {
        ok = write_at(fd, pieces[k], array_offset(k, total) + 4 * groups_before(part.start(k)));
        if (me == 0) ok = ok && write_at(fd, text_before(k, total), array_offset(k, total) - text_before(k, total).size());
    }
    if (me == 0) ok = ok && write_at(fd, text_before(array_count, total), array_offset(array_count, total) - text_before(array_count, total).size());
    ok = ok && ::fsync(fd) == 0;
    failure = ok ? "" : path + ": rank " + std::to_string(me) + " cannot write its part: " + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    try {
        agree(ranks, failure);
        if (me == 0) io::commit_temporary(temp, path);
    } catch (const ranks_agree_error&) {
        if (me == 0) ::unlink(temp.c_str());
        throw;
    } catch (const std::exception& e) {
        failure = e.what();  // the rename, on rank 0
    }
    agree(ranks, failure);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
    std::ostringstream o;
    o.precision(9);
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
    for (const auto& [t, file] : frames) o << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
    o << "  </Collection>\n</VTKFile>\n";
    io::write_file_atomically(path, o.str());
}

}  // namespace frnn::sim
