// Reading the input of a distributed query: offset reads of .npy and of binary .ply, every
// rank's own part of a text file, rank 0's read and a scatter for other .ply files, every
// rank's own slice of a generated set.
#include "mpi_input.hpp"

#include <climits>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "frnn/io/read.hpp"
#include "frnn/mpi/collective_error.hpp"

namespace frnn::app {
namespace {

template <class T>
MPI_Datatype mpi_type() {
    return sizeof(T) == 4 ? MPI_FLOAT : MPI_DOUBLE;
}

/// Rank 0 holds `all` (the other ranks an empty set): each rank receives its slice.
input_slice scatter(MPI_Comm comm, const io::point_set& all) {
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    std::uint64_t head[3] = {std::uint64_t(all.dimension), all.type() == io::precision::f32, all.size()};
    MPI_Bcast(head, 3, MPI_UINT64_T, 0, comm);
    input_slice s;
    s.total = head[2];
    s.first = io::slice_start(s.total, std::uint64_t(rank), std::uint64_t(size));
    s.points.dimension = int(head[0]);
    const std::uint64_t d = head[0];
    std::vector<int> counts(static_cast<std::size_t>(size)), starts(static_cast<std::size_t>(size));
    bool fits = s.total * d <= std::uint64_t(INT_MAX);
    for (int r = 0; r < size && fits; ++r) {
        starts[std::size_t(r)] = int(io::slice_start(s.total, std::uint64_t(r), std::uint64_t(size)) * d);
        counts[std::size_t(r)] = int(io::slice_start(s.total, std::uint64_t(r) + 1, std::uint64_t(size)) * d) - starts[std::size_t(r)];
    }
    // The same on every rank: MPI_Scatterv counts in int.
    mpi::throw_if_any(comm, fits ? "" : "the input's " + std::to_string(s.total) + " points are too many to scatter "
                                         "from rank 0 (2^31 coordinates); give them as .npy, which every rank reads itself");
    auto receive = [&]<class T>() {
        std::vector<T> mine(static_cast<std::size_t>(counts[std::size_t(rank)]));
        const T* from = rank == 0 ? std::get<std::vector<T>>(all.coords).data() : nullptr;
        MPI_Scatterv(from, counts.data(), starts.data(), mpi_type<T>(), mine.data(), counts[std::size_t(rank)],
                     mpi_type<T>(), 0, comm);
        s.points.coords = std::move(mine);
    };
    if (head[1]) receive.template operator()<float>();
    else receive.template operator()<double>();
    return s;
}

/// Every rank reads and parses its own part of a text file's lines (io::read_text_part); the
/// parts' summaries, gathered, give each its line and point numbers, header and columns.
input_slice read_text_slice(MPI_Comm comm, const std::string& file) {
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    std::string problem, lines;
    try {
        lines = io::read_text_part(file, std::uint64_t(rank), std::uint64_t(size));
    } catch (const std::exception& e) {
        problem = e.what();
    }
    mpi::throw_if_any(comm, problem);
    const io::text_part_summary mine = io::summarize_text_part(lines);
    std::vector<io::text_part_summary> parts(static_cast<std::size_t>(size));
    MPI_Allgather(&mine, sizeof mine, MPI_BYTE, parts.data(), sizeof mine, MPI_BYTE, comm);
    const io::text_context before = io::context_after(std::span(parts).first(static_cast<std::size_t>(rank)));
    const io::text_context all = io::context_after(parts);
    input_slice s;
    try {
        s.points = io::parse_text_part(lines, file, before);
    } catch (const std::exception& e) {
        problem = e.what();
    }
    // The lowest failing rank holds the file's first error: the parts are in file order.
    mpi::throw_if_any(comm, problem);
    s.points.dimension = all.columns == 0 ? 3 : int(all.columns);
    s.first = before.points;
    s.total = all.points;
    return s;
}

}  // namespace

input_slice read_input_slice(MPI_Comm comm, const query_args& a) {
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    if (!a.generate.empty()) {
        io::point_slice p = generate_slice(a.generate, a.dim, a.seed, std::uint64_t(rank), std::uint64_t(size));
        return {std::move(p.points), p.first, p.total};
    }
    std::string problem;
    if (lower_extension(a.input) == ".npy") {
        input_slice s;
        try {
            io::point_slice p = io::read_npy_slice(a.input, std::uint64_t(rank), std::uint64_t(size));
            s = {std::move(p.points), p.first, p.total};
        } catch (const std::exception& e) {
            problem = e.what();
        }
        mpi::throw_if_any(comm, problem);
        return s;
    }
    const std::string ext = lower_extension(a.input);
    if (ext == ".csv" || ext == ".txt" || ext == ".xyz") return read_text_slice(comm, a.input);
    if (ext == ".ply") {
        std::optional<io::point_slice> p;
        try {
            p = io::read_ply_slice(a.input, std::uint64_t(rank), std::uint64_t(size));
        } catch (const std::exception& e) {
            problem = e.what();
        }
        mpi::throw_if_any(comm, problem);
        // Slices only if every rank has one (ranks that see different files may disagree);
        // else rank 0 reads the file whole, below.
        int sliced = p.has_value();
        MPI_Allreduce(MPI_IN_PLACE, &sliced, 1, MPI_INT, MPI_MIN, comm);
        if (sliced) return {std::move(p->points), p->first, p->total};
    }
    io::point_set all;
    if (rank == 0) {
        try {
            all = io::read_points(a.input);
        } catch (const std::exception& e) {
            problem = e.what();
        }
    }
    mpi::throw_if_any(comm, problem);
    return scatter(comm, all);
}

}  // namespace frnn::app
