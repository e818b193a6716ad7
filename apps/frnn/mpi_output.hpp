// The one output file of a distributed `frnn query`: every rank's rows (its particles' neighbor
// lists in global ids) are gathered to rank 0, which puts them in global-id order and writes
// them with the single-process writer, atomically (temporary file + rename). So the file is
// byte-identical to the one `frnn query` writes alone.
// Cost on rank 0: memory and time O(N + entries), as the single-process tool; each rank sends
// its rows in one MPI_Gatherv per array (counts and displacements are int: 2^31 - 1 entries in
// all). Errors (a write failure on rank 0, too many entries) throw collective_error everywhere.
#pragma once
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "frnn/io/write.hpp"

namespace frnn::app {

/// A rank's rows: row k is particle ids[k], its neighbors' global ids by increasing id.
template <class T>
struct global_rows {
    std::vector<std::uint64_t> ids, lengths;
    std::vector<std::uint32_t> neighbors;
    std::vector<T> distances;  ///< empty when the output format has no distances
};

/// Collective: rank 0 writes the rows of every rank, `total` particles, to `file`.
template <class T>
void gather_and_write(MPI_Comm comm, const std::string& file, const global_rows<T>& mine, std::uint64_t total,
                      io::pair_filter filter);

}  // namespace frnn::app
