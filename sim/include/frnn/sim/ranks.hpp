// The ranks one simulation runs on, as its solver sees them: this rank's number, their count,
// and the collective exchanges of bytes it needs. `mpirun frnn sim` gives the tool's MPI
// implementation (apps/frnn/sim_ranks_mpi.cpp); the simulation library itself does not depend
// on MPI. Every member is a collective call: every rank makes it, in the same order.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "frnn/error.hpp"

namespace frnn::sim {

using rank_bytes = std::vector<char>;

class rank_comm {
public:
    virtual ~rank_comm() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Every rank sends send[q] to rank q (send.size() == size()); returns what each rank sent
    /// this one, indexed by the sender.
    virtual std::vector<rank_bytes> exchange(const std::vector<rank_bytes>& send) = 0;
    /// Every rank's `mine`, indexed by rank, on every rank.
    virtual std::vector<rank_bytes> all_gather(const rank_bytes& mine) = 0;
    /// Every rank's `mine` on rank 0, indexed by rank; an empty list on the others.
    virtual std::vector<rank_bytes> gather(const rank_bytes& mine) = 0;
};

/// When the ranks' parts of the domain move with the fluid: every `check_every` steps, if the
/// most loaded rank holds more than (1 + imbalance) times the mean of the particles, the cut is
/// made anew from where the particles are. The result does not depend on it.
struct balance_options {
    double imbalance = 0.1;
    std::uint32_t check_every = 20;
};

/// What the ranks did over a run (solver::ranks_report).
struct ranks_report {
    struct rank {
        std::size_t particles = 0, ghosts = 0;  ///< at the end
        std::uint64_t bytes_sent = 0;           ///< particles, ghosts and ghost refreshes, over the run
        /// Mean milliseconds per step (over the steps that ended before the report; without
        /// output): in the exchanges (moving particles and ghosts, sorting them in, refreshing
        /// the ghosts, the reductions), of which waiting inside collective calls (for the data,
        /// or for slower ranks), and the rest of the step.
        double exchange_ms = 0, waiting_ms = 0, local_ms = 0;
    };
    std::vector<rank> per_rank;
    std::size_t checks = 0, rebalances = 0;
    double largest_imbalance = 0;  ///< the largest of (most loaded rank / mean) at the checks
    double mean_imbalance = 0;     ///< its mean over the checks
};

/// An error that every rank raised at the same point with the same message (a failed check of
/// the whole simulation, or a failed set-up), so that rank 0 alone reports it.
struct ranks_agree_error : error {
    using error::error;
};

/// Runs f on every rank (in one process: just runs it). When it throws on some rank, every
/// rank throws ranks_agree_error with the message of the first rank that failed: a set-up
/// step that may fail on some ranks only (a file one node cannot read) stops them together.
void on_every_rank(const std::shared_ptr<rank_comm>& ranks, const std::function<void()>& f);

}  // namespace frnn::sim
