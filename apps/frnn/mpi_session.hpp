// MPI for the life of a distributed command (`mpirun frnn query`, `mpirun frnn sim`). MPI calls
// come from the main thread only (frnn's worker threads never call MPI).
#pragma once
#include <mpi.h>

namespace frnn::app {

class mpi_session {
public:
    mpi_session() {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    }
    ~mpi_session() { MPI_Finalize(); }
    mpi_session(const mpi_session&) = delete;
    mpi_session& operator=(const mpi_session&) = delete;
};

}  // namespace frnn::app
