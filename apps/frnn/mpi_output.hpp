// The one output file of a distributed `frnn query`, written by every rank at once: the rows
// (each particle's neighbor list in global ids) move to the rank that owns their id, in
// contiguous id ranges of about N/P, and each rank encodes its range with the single-process
// writer's encoder (frnn/io/neighbor_file.hpp) and writes it in place with MPI-IO; rank 0
// writes the frame (headers, and the zip directory of .npz from every rank's CRCs). The file
// is byte-identical to the one `frnn query` writes alone, and appears only complete: it is
// written under a temporary name that rank 0 renames at the end.
// Every rank must see the output's folder (as every rank reads an .npy input itself).
// Cost per rank: memory and time O(N/P + its rows' entries), two all-to-all exchanges of counts
// and rows (MPI int counts: at most 2^31 - 1 entries sent or received by a rank). Errors (a
// folder that cannot be written, a failed write on any rank, too many entries) throw
// collective_error everywhere and leave no file.
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

/// Collective: writes the rows of every rank, `total` particles, to `file` (format by extension).
/// Takes `mine` to free it once the rows are packed for their owners.
template <class T>
void write_distributed(MPI_Comm comm, const std::string& file, global_rows<T> mine, std::uint64_t total,
                       io::pair_filter filter);

}  // namespace frnn::app
