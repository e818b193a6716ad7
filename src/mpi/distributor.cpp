// The distributor's plan: every local particle is one export, to its destination.
#include "frnn/mpi/distributor.hpp"

#include <numeric>

namespace frnn::mpi {

distributor::distributor(MPI_Comm comm, std::span<const int> destinations) : local_size_(destinations.size()) {
    int size = 0;
    MPI_Comm_size(comm, &size);
    std::string problem;
    for (std::size_t i = 0; i < destinations.size() && problem.empty(); ++i)
        if (destinations[i] < 0 || destinations[i] >= size)
            problem = "particle " + std::to_string(i) + " has destination rank " + std::to_string(destinations[i]) +
                      " of " + std::to_string(size);
    throw_if_any(comm, problem);
    std::vector<std::uint32_t> sources(destinations.size());
    std::iota(sources.begin(), sources.end(), 0u);
    plan_ = communication_plan(comm, destinations, sources);
}

void distributor::check_size(std::size_t size, std::size_t components, const char* what) const {
    std::string problem;
    if (size != local_size_ * components)
        problem = std::string(what) + ": field has " + std::to_string(size) + " values, expected " +
                  std::to_string(local_size_) + " particles x " + std::to_string(components);
    throw_if_any(plan_.comm(), problem);
}

std::vector<std::uint64_t> distributor::row_lengths(std::span<const std::uint64_t> offsets, std::size_t values) const {
    std::string problem;
    if (offsets.size() != local_size_ + 1)
        problem = "migrate: " + std::to_string(offsets.size()) + " row offsets, expected " + std::to_string(local_size_ + 1);
    else if (offsets[0] != 0 || offsets.back() != values)
        problem = "migrate: row offsets run from " + std::to_string(offsets[0]) + " to " + std::to_string(offsets.back()) +
                  ", expected 0 to " + std::to_string(values) + " (the number of values)";
    for (std::size_t i = 0; problem.empty() && i < local_size_; ++i)
        if (offsets[i + 1] < offsets[i]) problem = "migrate: row offsets decrease at particle " + std::to_string(i);
    throw_if_any(plan_.comm(), problem);
    std::vector<std::uint64_t> lengths(local_size_);
    for (std::size_t i = 0; i < local_size_; ++i) lengths[i] = offsets[i + 1] - offsets[i];
    return lengths;
}

}  // namespace frnn::mpi
