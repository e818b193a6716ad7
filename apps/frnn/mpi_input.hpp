// This rank's share of the points of a distributed `frnn query`: rows [first, first + size) of
// the input, in rank order.
//   .npy        every rank reads the header and its own rows' bytes (plain offset reads), the
//               nearly equal slices read_npy_slice defines (total * rank / ranks ...);
//   text        every rank reads and parses the lines that start in its share of the bytes
//               (io::read_text_part), so its share of the points is nearly equal when the
//               lines are;
//   .ply        binary files without lists before or in the vertices: every rank reads the
//               header and its own slice of vertices (io::read_ply_slice); other .ply files
//               rank 0 reads whole and scatters;
//   --generate  every rank draws its own slice (the generators skip the draws of the points
//               before it).
// Bad input throws frnn::mpi::collective_error on every rank (CLI::ValidationError for a bad
// --generate, on every rank alike).
#pragma once
#include <mpi.h>

#include <cstdint>

#include "frnn/io/point_set.hpp"
#include "query_args.hpp"

namespace frnn::app {

struct input_slice {
    io::point_set points;
    std::uint64_t first = 0, total = 0;
};

input_slice read_input_slice(MPI_Comm comm, const query_args& a);

}  // namespace frnn::app
