// Collective error checks: a rank that finds bad input must not leave the others waiting in a
// collective call. Every rank calls throw_if_any with its own finding (empty: nothing wrong);
// if any rank found something, every rank throws the same collective_error (an frnn::error),
// with the message of the lowest failing rank ("rank 2: ..."). Any other exception from frnn::mpi
// was thrown on one rank only: the others may be waiting for it, so a program should then call
// MPI_Abort rather than MPI_Finalize.
// Cost: one MPI_Allreduce of an int, plus one broadcast of the message when something failed.
// Rank safety: collective over `comm` (every rank must call it, in the same order as its other
// collectives). Thread safety: call from one thread per rank.
#pragma once
#include <mpi.h>

#include <span>
#include <string>
#include <vector>

#include "frnn/error.hpp"

namespace frnn::mpi {

/// The error every rank of a communicator throws alike: safe to finalize MPI after it.
class collective_error : public error {
public:
    explicit collective_error(const std::string& what) : error(what) {}
};

/// Throws collective_error on every rank of `comm` when `local_error` is non-empty on any rank.
void throw_if_any(MPI_Comm comm, const std::string& local_error);

/// Throws collective_error on every rank unless every rank passed the same `values` (bit for bit; `what` names
/// them in the message, e.g. "radius"): rank 0's values are the reference.
void require_same(MPI_Comm comm, std::span<const double> values, const std::string& what);

}  // namespace frnn::mpi
