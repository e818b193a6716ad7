// `mpirun -np P frnn sim ...`: one simulation over the launcher's ranks (frnn/sim/ranks.hpp),
// with the one-process result. Taken when a launcher started several ranks (launcher.hpp).
#pragma once
#include <functional>

#include "frnn/error.hpp"
#include "frnn/sim/run.hpp"

namespace frnn::app {

#if defined(FRNN_MPI_AVAILABLE)
/// Every rank runs this: starts MPI, calls run(options with the ranks) and ends MPI. Rank 0
/// reports an error that every rank raised; an error on one rank alone ends the job.
void run_sim_across_ranks(sim::run_options options, const std::function<void(const sim::run_options&)>& run);
#else
[[noreturn]] inline void run_sim_across_ranks(sim::run_options, const std::function<void(const sim::run_options&)>&) {
    throw error("started by mpirun, but this frnn was built without MPI (it needs libopenmpi-dev at build time)");
}
#endif

}  // namespace frnn::app
