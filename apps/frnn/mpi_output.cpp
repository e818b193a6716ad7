// Gathering the rows to rank 0 and writing them there.
#include "mpi_output.hpp"

#include <algorithm>
#include <climits>
#include <exception>
#include <numeric>

#include "frnn/mpi/collective_error.hpp"

namespace frnn::app {
namespace {

template <class U>
MPI_Datatype mpi_type() {
    if constexpr (sizeof(U) == 4) return std::is_floating_point_v<U> ? MPI_FLOAT : MPI_UINT32_T;
    else return std::is_floating_point_v<U> ? MPI_DOUBLE : MPI_UINT64_T;
}

/// Rank 0 receives every rank's `mine` in rank order (counts and starts as gathered).
template <class U>
std::vector<U> gather(MPI_Comm comm, const std::vector<U>& mine, const std::vector<int>& counts,
                      const std::vector<int>& starts) {
    std::vector<U> all(counts.empty() ? 0 : std::size_t(starts.back()) + std::size_t(counts.back()));
    MPI_Gatherv(mine.data(), int(mine.size()), mpi_type<U>(), all.data(), counts.data(), starts.data(), mpi_type<U>(),
                0, comm);
    return all;
}

/// Rank 0 learns each rank's count of `n` and where its part starts; an error on every rank when
/// the parts do not fit MPI's int counts.
void layout(MPI_Comm comm, std::size_t n, const char* what, std::vector<int>& counts, std::vector<int>& starts) {
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    unsigned long long mine = n, sum = 0;
    MPI_Allreduce(&mine, &sum, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    mpi::throw_if_any(comm, sum <= INT_MAX ? "" : "the output's " + std::to_string(sum) + " " + what +
                                                      " exceed what rank 0 can gather (2^31 - 1)");
    const int count = int(n);
    if (rank == 0) counts.assign(std::size_t(size), 0);
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
    if (rank == 0) {
        starts.assign(std::size_t(size), 0);
        std::exclusive_scan(counts.begin(), counts.end(), starts.begin(), 0);
    }
}

}  // namespace

template <class T>
void gather_and_write(MPI_Comm comm, const std::string& file, const global_rows<T>& mine, std::uint64_t total,
                      io::pair_filter filter) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    std::vector<int> row_counts, row_starts, entry_counts, entry_starts;
    layout(comm, mine.ids.size(), "rows", row_counts, row_starts);
    layout(comm, mine.neighbors.size(), "pairs", entry_counts, entry_starts);
    const std::vector<std::uint64_t> ids = gather(comm, mine.ids, row_counts, row_starts);
    const std::vector<std::uint64_t> lengths = gather(comm, mine.lengths, row_counts, row_starts);
    const std::vector<std::uint32_t> neighbors = gather(comm, mine.neighbors, entry_counts, entry_starts);
    int with_distances = !mine.distances.empty() || mine.neighbors.empty();
    MPI_Allreduce(MPI_IN_PLACE, &with_distances, 1, MPI_INT, MPI_MIN, comm);
    const std::vector<T> distances =
        with_distances ? gather(comm, mine.distances, entry_counts, entry_starts) : std::vector<T>{};
    std::string problem;
    if (rank == 0) {
        try {
            // Rows in global-id order: where each row's entries start, then each row in place.
            csr<T> lists;
            lists.offsets.assign(total + 1, 0);
            for (std::size_t k = 0; k < ids.size(); ++k) lists.offsets[ids[k] + 1] = lengths[k];
            std::inclusive_scan(lists.offsets.begin(), lists.offsets.end(), lists.offsets.begin());
            lists.indices.resize(neighbors.size());
            if (with_distances) lists.distances.resize(neighbors.size());
            std::size_t from = 0;
            for (std::size_t k = 0; k < ids.size(); ++k) {
                const std::uint64_t to = lists.offsets[ids[k]];
                std::copy_n(neighbors.begin() + std::ptrdiff_t(from), lengths[k], lists.indices.begin() + std::ptrdiff_t(to));
                if (with_distances)
                    std::copy_n(distances.begin() + std::ptrdiff_t(from), lengths[k], lists.distances.begin() + std::ptrdiff_t(to));
                from += lengths[k];
            }
            io::write_neighbors(file, lists, filter);
        } catch (const std::exception& e) {
            problem = e.what();
        }
    }
    mpi::throw_if_any(comm, problem);
}

template void gather_and_write(MPI_Comm, const std::string&, const global_rows<float>&, std::uint64_t, io::pair_filter);
template void gather_and_write(MPI_Comm, const std::string&, const global_rows<double>&, std::uint64_t, io::pair_filter);

}  // namespace frnn::app
