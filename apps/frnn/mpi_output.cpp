// Moving the rows to the owners of their ids and writing them in place.
#include "mpi_output.hpp"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <numeric>

#include "frnn/io/atomic_file.hpp"
#include "frnn/io/neighbor_file.hpp"
#include "frnn/mpi/collective_error.hpp"

namespace frnn::app {
namespace {

template <class U>
MPI_Datatype mpi_type() {
    if constexpr (sizeof(U) == 4) return std::is_floating_point_v<U> ? MPI_FLOAT : MPI_UINT32_T;
    else return std::is_floating_point_v<U> ? MPI_DOUBLE : MPI_UINT64_T;
}

struct communicator {
    MPI_Comm comm;
    int rank = 0, size = 1;
    explicit communicator(MPI_Comm c) : comm(c) {
        MPI_Comm_rank(c, &rank);
        MPI_Comm_size(c, &size);
    }
};

/// The first id of rank k's range: ceil(k total / P), so rank k owns the ids whose
/// floor(id P / total) is k (products below 2^63: ids and total below 2^32, P below 2^31).
std::uint64_t first_id(std::uint64_t k, std::uint64_t total, std::uint64_t ranks) { return (k * total + ranks - 1) / ranks; }

/// Per-rank counts and starts of one all-to-all array, as MPI's ints.
struct int_layout {
    std::vector<int> counts, starts;
};

int_layout to_ints(const std::vector<std::uint64_t>& counts) {
    int_layout l{std::vector<int>(counts.size()), std::vector<int>(counts.size())};
    std::uint64_t at = 0;
    for (std::size_t k = 0; k < counts.size(); ++k) {
        l.counts[k] = int(counts[k]);
        l.starts[k] = int(at);
        at += counts[k];
    }
    return l;
}

/// MPI_Alltoallv of `out` (freed on return) into a new array.
template <class U>
std::vector<U> exchange(MPI_Comm comm, std::vector<U> out, const int_layout& sent, const int_layout& received) {
    std::vector<U> in(received.counts.empty() ? 0 : std::size_t(received.starts.back()) + std::size_t(received.counts.back()));
    MPI_Alltoallv(out.data(), sent.counts.data(), sent.starts.data(), mpi_type<U>(), in.data(), received.counts.data(),
                  received.starts.data(), mpi_type<U>(), comm);
    return in;
}

/// This rank's id range [first_id(rank), first_id(rank + 1)) as lists in id order, from the
/// rows of every rank.
template <class T>
csr<T> rows_by_id(const communicator& c, global_rows<T>&& mine, std::uint64_t total, bool distances) {
    const std::size_t P = std::size_t(c.size), n = mine.ids.size();
    std::vector<std::uint64_t> entry_start(n + 1, 0);
    std::inclusive_scan(mine.lengths.begin(), mine.lengths.end(), entry_start.begin() + 1);
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return mine.ids[a] < mine.ids[b]; });

    // Rows and entries per destination (monotone in id: each destination's rows are contiguous).
    std::vector<std::uint64_t> send_rows(P, 0), send_entries(P, 0);
    global_rows<T> out;
    out.ids.reserve(n);
    out.lengths.reserve(n);
    out.neighbors.reserve(mine.neighbors.size());
    if (distances) out.distances.reserve(mine.neighbors.size());
    for (std::size_t k : order) {
        const std::size_t to = std::size_t(mine.ids[k] * P / total);
        ++send_rows[to];
        send_entries[to] += mine.lengths[k];
        out.ids.push_back(mine.ids[k]);
        out.lengths.push_back(mine.lengths[k]);
        const auto from = std::ptrdiff_t(entry_start[k]), to_end = std::ptrdiff_t(entry_start[k + 1]);
        out.neighbors.insert(out.neighbors.end(), mine.neighbors.begin() + from, mine.neighbors.begin() + to_end);
        if (distances) out.distances.insert(out.distances.end(), mine.distances.begin() + from, mine.distances.begin() + to_end);
    }
    mine = {};  // each array is freed as soon as it was sent (exchange takes it)
    std::vector<std::uint64_t> recv_rows(P), recv_entries(P);
    MPI_Alltoall(send_rows.data(), 1, MPI_UINT64_T, recv_rows.data(), 1, MPI_UINT64_T, c.comm);
    MPI_Alltoall(send_entries.data(), 1, MPI_UINT64_T, recv_entries.data(), 1, MPI_UINT64_T, c.comm);
    const std::uint64_t sent = std::accumulate(send_entries.begin(), send_entries.end(), std::uint64_t(0));
    const std::uint64_t received = std::accumulate(recv_entries.begin(), recv_entries.end(), std::uint64_t(0));
    const std::uint64_t rows_in = std::accumulate(recv_rows.begin(), recv_rows.end(), std::uint64_t(0));
    mpi::throw_if_any(c.comm, std::max(sent, received) <= INT_MAX && n <= INT_MAX && rows_in <= INT_MAX
                                  ? ""
                                  : "the output's rows of this rank (" + std::to_string(std::max(sent, received)) +
                                        " entries) exceed what one MPI exchange carries (2^31 - 1)");

    const int_layout row_out = to_ints(send_rows), row_in = to_ints(recv_rows);
    const int_layout entry_out = to_ints(send_entries), entry_in = to_ints(recv_entries);
    const std::vector<std::uint64_t> ids = exchange(c.comm, std::move(out.ids), row_out, row_in);
    const std::vector<std::uint64_t> lengths = exchange(c.comm, std::move(out.lengths), row_out, row_in);
    const std::vector<std::uint32_t> neighbors = exchange(c.comm, std::move(out.neighbors), entry_out, entry_in);
    const std::vector<T> dist = distances ? exchange(c.comm, std::move(out.distances), entry_out, entry_in) : std::vector<T>{};

    // Rows arrive sorted from each rank; placed by id, each in its slot.
    const std::uint64_t lo = first_id(std::uint64_t(c.rank), total, P), hi = first_id(std::uint64_t(c.rank) + 1, total, P);
    csr<T> lists;
    lists.offsets.assign(hi - lo + 1, 0);
    for (std::size_t k = 0; k < ids.size(); ++k) lists.offsets[ids[k] - lo + 1] = lengths[k];
    std::inclusive_scan(lists.offsets.begin(), lists.offsets.end(), lists.offsets.begin());
    lists.indices.resize(neighbors.size());
    if (distances) lists.distances.resize(neighbors.size());
    std::size_t from = 0;
    for (std::size_t k = 0; k < ids.size(); ++k) {
        const auto to = std::ptrdiff_t(lists.offsets[ids[k] - lo]), count = std::ptrdiff_t(lengths[k]);
        std::copy_n(neighbors.begin() + std::ptrdiff_t(from), count, lists.indices.begin() + to);
        if (distances) std::copy_n(dist.begin() + std::ptrdiff_t(from), count, lists.distances.begin() + to);
        from += lengths[k];
    }
    return lists;
}

/// Writes `bytes` at `offset` of the open file; an error message, or empty.
std::string write_at(MPI_File fh, std::uint64_t offset, std::string_view bytes) {
    constexpr std::size_t piece = std::size_t(1) << 30;  // MPI counts are int
    for (std::size_t done = 0; done < bytes.size();) {
        const std::size_t n = std::min(piece, bytes.size() - done);
        MPI_Status status;
        const int rc = MPI_File_write_at(fh, MPI_Offset(offset + done), bytes.data() + done, int(n), MPI_BYTE, &status);
        int written = 0;
        if (rc == MPI_SUCCESS) MPI_Get_count(&status, MPI_BYTE, &written);
        if (rc != MPI_SUCCESS || std::size_t(written) != n) {
            char text[MPI_MAX_ERROR_STRING] = "short write";
            int length = 0;
            if (rc != MPI_SUCCESS) MPI_Error_string(rc, text, &length);
            return std::string("write failed: ") + text;
        }
        done += n;
    }
    return {};
}

/// A temporary file beside the target that every rank writes through MPI-IO; rank 0 creates
/// it, and removes it unless it was committed.
class shared_temporary {
public:
    shared_temporary(const communicator& c, const std::string& target) : c_(c), target_(target) {
        std::string problem;
        if (c.rank == 0) {
            path_ = io::temporary_path_beside(target).string();
            if (std::FILE* f = std::fopen(path_.c_str(), "wbx")) {
                std::fclose(f);
                created_ = true;
            } else {
                problem = target + ": cannot create temporary file " + path_ + ": " + std::strerror(errno);
            }
        }
        unsigned long long length = path_.size();
        MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, c.comm);
        path_.resize(length);
        MPI_Bcast(path_.data(), int(length), MPI_CHAR, 0, c.comm);
        mpi::throw_if_any(c.comm, problem);
        const int rc = MPI_File_open(c.comm, path_.c_str(), MPI_MODE_WRONLY, MPI_INFO_NULL, &fh_);
        open_ = rc == MPI_SUCCESS;
        check(open_ ? "" : target + ": cannot open " + path_ + " on every rank: " + error_text(rc));
    }
    /// Never a collective call: a rank may unwind alone (the tool then aborts the job).
    ~shared_temporary() {
        if (created_) std::remove(path_.c_str());
    }
    shared_temporary(const shared_temporary&) = delete;
    shared_temporary& operator=(const shared_temporary&) = delete;

    MPI_File handle() const { return fh_; }

    /// Collective: throws on every rank (the file removed) when any rank has a problem.
    void check(const std::string& problem) {
        int failed = !problem.empty();
        MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, c_.comm);
        if (failed && open_) MPI_File_close(&fh_), open_ = false;
        mpi::throw_if_any(c_.comm, problem);
    }

    /// Collective: flushes and closes the file, and rank 0 renames it over the target.
    void commit() {
        int rc = MPI_File_sync(fh_);
        check(rc == MPI_SUCCESS ? "" : target_ + ": write failed: " + error_text(rc));
        rc = MPI_File_close(&fh_);
        open_ = false;
        check(rc == MPI_SUCCESS ? "" : target_ + ": write failed: " + error_text(rc));
        std::string problem;
        if (c_.rank == 0) {
            try {
                io::commit_temporary(path_, target_);
                created_ = false;
            } catch (const std::exception& e) {
                problem = e.what();
            }
        }
        mpi::throw_if_any(c_.comm, problem);
    }

private:
    static std::string error_text(int rc) {
        char text[MPI_MAX_ERROR_STRING];
        int length = 0;
        MPI_Error_string(rc, text, &length);
        return std::string(text, std::size_t(length));
    }

    const communicator& c_;
    std::string target_, path_;
    MPI_File fh_ = MPI_FILE_NULL;
    bool created_ = false, open_ = false;
};

}  // namespace

template <class T>
void write_distributed(MPI_Comm comm, const std::string& file, global_rows<T> mine, std::uint64_t total,
                       io::pair_filter filter) {
    const communicator c(comm);
    io::neighbor_format format{};
    std::string problem;
    try {
        format = io::neighbor_format_of(file);
    } catch (const std::exception& e) {
        problem = e.what();
    }
    mpi::throw_if_any(comm, problem);
    const int members = io::member_count(format);
    const csr<T> lists = rows_by_id(c, std::move(mine), total, io::needs_distances(format));

    // Where this rank's rows and entries fall in the file's.
    const std::uint64_t lo = first_id(std::uint64_t(c.rank), total, std::uint64_t(c.size));
    std::uint64_t kept = 0;
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            kept += filter == io::pair_filter::all || lists.indices[k] >= lo + i;
    std::uint64_t mine_entries = lists.size(), entries_before = 0, all_entries = 0, all_kept = 0;
    MPI_Exscan(&mine_entries, &entries_before, 1, MPI_UINT64_T, MPI_SUM, comm);
    if (c.rank == 0) entries_before = 0;  // MPI_Exscan leaves rank 0's undefined
    MPI_Allreduce(&mine_entries, &all_entries, 1, MPI_UINT64_T, MPI_SUM, comm);
    MPI_Allreduce(&kept, &all_kept, 1, MPI_UINT64_T, MPI_SUM, comm);

    // Member m's bytes of this rank's rows, a block of rows at a time: a rank never holds its
    // whole part of the file.
    const bool closes = c.rank == c.size - 1;
    auto for_each_block = [&](int m, auto&& f) {
        constexpr std::size_t block_rows = 1 << 13;
        std::size_t b = 0;
        std::string bytes;
        do {  // at least one block: the last rank closes the .npz offsets
            const std::size_t e = std::min(lists.rows(), b + block_rows);
            io::encode_rows(bytes, format, m, lists, b, e, {lo, entries_before}, filter, closes && e == lists.rows());
            if (!f(bytes)) return;
            b = e;
        } while (b < lists.rows());
    };
    // Sizes first, every rank's, to place each part: those of .npy and .npz follow from the
    // counts; a .csv line has no fixed length, so .csv is encoded once to measure it.
    std::vector<std::uint64_t> sizes(3, 0), all_sizes(3 * std::size_t(c.size));
    for (int m = 0; m < members; ++m) {
        if (const auto size = io::encoded_size(format, m, lists.rows(), mine_entries, kept, closes))
            sizes[std::size_t(m)] = *size;
        else
            for_each_block(m, [&](const std::string& bytes) { return sizes[std::size_t(m)] += bytes.size(), true; });
    }
    MPI_Allgather(sizes.data(), 3, MPI_UINT64_T, all_sizes.data(), 3, MPI_UINT64_T, comm);
    const std::uint64_t entries = format == io::neighbor_format::lists_npz ? all_entries : all_kept;
    io::neighbor_frame frame;
    try {
        frame = io::frame_of(format, file, total, entries);  // lengths only: CRCs come last
    } catch (const std::exception& e) {
        problem = e.what();  // the same on every rank
    }
    mpi::throw_if_any(comm, problem);
    // Where each member's frame starts (and, last, the end's), and where this rank's part of it.
    const std::size_t member_count = std::size_t(members);
    std::vector<std::uint64_t> member_at(member_count + 1), mine_at(member_count);
    std::uint64_t at = 0;
    for (std::size_t m = 0; m < member_count; ++m) {
        member_at[m] = at;
        at += frame.before[m].size();
        mine_at[m] = at;
        for (std::size_t k = 0; k < std::size_t(c.size); ++k) {
            if (k < std::size_t(c.rank)) mine_at[m] += all_sizes[3 * k + m];
            at += all_sizes[3 * k + m];
        }
    }
    member_at[member_count] = at;

    shared_temporary out(c, file);
    std::vector<std::uint32_t> crcs(3, 0), all_crcs(3 * std::size_t(c.size));
    for (int m = 0; m < members; ++m) {
        io::checksum sum;
        for_each_block(m, [&](const std::string& bytes) {
            problem = write_at(out.handle(), mine_at[std::size_t(m)] + sum.bytes, bytes);
            sum = io::extended(sum, bytes);
            return problem.empty();
        });
        crcs[std::size_t(m)] = sum.crc;
        if (!problem.empty()) break;
    }
    // The frame, with the CRCs of the members' whole bodies.
    MPI_Allgather(crcs.data(), 3, MPI_UINT32_T, all_crcs.data(), 3, MPI_UINT32_T, comm);
    std::vector<std::uint32_t> body_crcs(3, 0);
    for (std::size_t m = 0; m < 3; ++m) {
        io::checksum whole;
        for (std::size_t k = 0; k < std::size_t(c.size); ++k) whole = io::concatenate(whole, {all_crcs[3 * k + m], all_sizes[3 * k + m]});
        body_crcs[m] = whole.crc;
    }
    if (c.rank == 0 && problem.empty()) {
        frame = io::frame_of(format, file, total, entries, body_crcs);
        for (std::size_t m = 0; m < member_count && problem.empty(); ++m)
            problem = write_at(out.handle(), member_at[m], frame.before[m]);
        if (problem.empty()) problem = write_at(out.handle(), member_at[member_count], frame.after);
    }
    out.check(problem.empty() ? "" : file + ": " + problem);
    out.commit();
}

template void write_distributed(MPI_Comm, const std::string&, global_rows<float>, std::uint64_t, io::pair_filter);
template void write_distributed(MPI_Comm, const std::string&, global_rows<double>, std::uint64_t, io::pair_filter);

}  // namespace frnn::app
