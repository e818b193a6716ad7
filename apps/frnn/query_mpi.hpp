// `mpirun -np P frnn query ...`: the distributed path of `frnn query` (frnn::mpi). It is taken
// when an MPI launcher started the process, which the environment tells: Open MPI's mpirun sets
// OMPI_COMM_WORLD_SIZE, PMIx launchers PMIX_RANK, MPICH's Hydra and Slurm PMI_RANK. Plain `frnn`
// sees none of them and never initialises MPI (nor needs an MPI runtime to start).
#pragma once
#include <cstdlib>

#include "frnn/error.hpp"
#include "query_args.hpp"

namespace frnn::app {

inline bool launched_by_mpirun() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(name)) return true;
    return false;
}

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
