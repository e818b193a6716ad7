// Whether an MPI launcher (mpirun, mpiexec) started this process, and as which rank of
// how many: read from the variables launchers set, so that it works in a tool built without
// MPI too.
#pragma once
#include <cstdlib>
#include <initializer_list>

namespace frnn::app {

/// The first of these variables that is set, as a number; -1 when none is.
inline long launcher_value(std::initializer_list<const char*> names) {
    for (const char* name : names)
        if (const char* v = std::getenv(name)) return std::strtol(v, nullptr, 10);
    return -1;
}

/// Started by a launcher: Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE, PMIx launchers
/// PMIX_RANK, MPICH's Hydra and Slurm (with PMI) PMI_RANK.
inline bool launched_by_mpirun() { return launcher_value({"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) >= 0; }

/// Ranks the launcher started: 1 without one; 2 when it says a rank but not how many (it is
/// then refused as if several ran: the safe side).
inline long launcher_ranks() {
    if (!launched_by_mpirun()) return 1;
    const long size = launcher_value({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"});
    return size >= 1 ? size : 2;
}

/// This process's rank under the launcher (0 without one).
inline long launcher_rank() {
    const long rank = launcher_value({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"});
    return rank >= 0 ? rank : 0;
}

}  // namespace frnn::app
