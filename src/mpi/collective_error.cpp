// The collective error checks: an Allreduce finds the lowest failing rank, which broadcasts
// its message, so that every rank throws the same error instead of waiting for the others.
#include <cstring>

#include "frnn/mpi/collective_error.hpp"

namespace frnn::mpi {

void throw_if_any(MPI_Comm comm, const std::string& local_error) {
    int rank = 0, size = 0;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
    const int mine = local_error.empty() ? size : rank;
    int first = size;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == size) return;
    unsigned long long length = local_error.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, first, comm);
    std::string message = rank == first ? local_error : std::string(length, ' ');
    MPI_Bcast(message.data(), int(length), MPI_CHAR, first, comm);
    throw collective_error("rank " + std::to_string(first) + ": " + message);
}

void require_same(MPI_Comm comm, std::span<const double> values, const std::string& what) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    unsigned long long count = values.size();
    MPI_Bcast(&count, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
    std::vector<double> reference(count);
    if (rank == 0) reference.assign(values.begin(), values.end());
    MPI_Bcast(reference.data(), int(count), MPI_DOUBLE, 0, comm);
    std::string problem;
    // Bit for bit: a NaN differs from everything, even from itself.
    if (count != values.size() || std::memcmp(reference.data(), values.data(), count * sizeof(double)) != 0) {
        auto text = [](std::span<const double> v) {
            std::string s;
            for (double x : v) {
                if (!s.empty()) s += ' ';
                s += std::to_string(x);
            }
            return "(" + s + ")";
        };
        problem = what + " " + text(values) + " differs from rank 0's " + text(reference);
    }
    throw_if_any(comm, problem);
}

}  // namespace frnn::mpi
