// `mpirun -np P frnn query ...`: the distributed path of `frnn query` (frnn::mpi). It is taken
// when an MPI launcher started the process, which the environment tells (launcher.hpp). Plain
// `frnn` sees none of it and never initialises MPI (nor needs an MPI runtime to start).
#pragma once
#include <cstdlib>

#include "frnn/error.hpp"
#include "launcher.hpp"
#include "query_args.hpp"

namespace frnn::app {

#ifdef FRNN_MPI_AVAILABLE
/// Every rank runs this: reads its share of the input, searches across the ranks and rank 0
/// writes the one output file and prints the summary.
void run_query_mpi(const query_args& a);
#else
[[noreturn]] inline void run_query_mpi(const query_args&) {
    throw error("started by mpirun, but this frnn was built without MPI (it needs libopenmpi-dev at build time)");
}
#endif

}  // namespace frnn::app
