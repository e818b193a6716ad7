// Helpers of the MPI tests: each rank's slice of a point set, the single-process reference
// pairs (frnn's brute-force oracle) as global ids, and collective checks.
#pragma once
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "frnn/brute_force.hpp"
#include "frnn/error.hpp"

namespace frnn::test {

inline int world_rank() {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}
inline int world_size() {
    int s = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &s);
    return s;
}

/// A pair (id of a local particle, id of its neighbor) and their distance.
template <class T>
using pair_t = std::tuple<std::uint64_t, std::uint64_t, T>;

/// This rank's slice of `points` (D values each) with global ids: contiguous blocks by default,
/// everything on rank 0 with `all_on_rank0` (the other ranks start empty).
template <class T, int D>
void slice(const std::vector<T>& points, bool all_on_rank0, std::vector<T>& coords, std::vector<std::uint64_t>& ids) {
    const std::size_t n = points.size() / D, rank = std::size_t(world_rank()), size = std::size_t(world_size());
    const std::size_t begin = all_on_rank0 ? (rank == 0 ? 0 : n) : n * rank / size;
    const std::size_t end = all_on_rank0 ? n : n * (rank + 1) / size;
    coords.assign(points.begin() + std::ptrdiff_t(begin * D), points.begin() + std::ptrdiff_t(end * D));
    ids.resize(end - begin);
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = begin + i;
}

/// The single-process pairs of the particles `local_ids`, with the oracle's distances.
template <class T, int D>
std::vector<pair_t<T>> reference_pairs(const std::vector<T>& points, T radius, std::span<const double> periodic,
                                       std::span<const std::uint64_t> local_ids) {
    const csr<T> lists = brute_force_lists<T, D>(points, points, radius, true, periodic);
    std::vector<pair_t<T>> out;
    for (std::uint64_t i : local_ids)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            out.emplace_back(i, lists.indices[k], lists.distances[k]);
    std::sort(out.begin(), out.end());
    return out;
}

/// Every id 0 .. n-1 is on exactly one rank.
inline void expect_partition(std::span<const std::uint64_t> local_ids, std::size_t n) {
    int count = int(local_ids.size());
    const std::size_t ranks = static_cast<std::size_t>(world_size());
    std::vector<int> counts(ranks), starts(ranks + 1, 0);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    for (std::size_t r = 0; r < counts.size(); ++r) starts[r + 1] = starts[r] + counts[r];
    std::vector<std::uint64_t> all(std::size_t(starts.back()));
    MPI_Allgatherv(local_ids.data(), count, MPI_UINT64_T, all.data(), counts.data(), starts.data(), MPI_UINT64_T,
                   MPI_COMM_WORLD);
    std::sort(all.begin(), all.end());
    std::vector<std::uint64_t> expected(n);
    for (std::size_t i = 0; i < n; ++i) expected[i] = i;
    EXPECT_EQ(all, expected) << "particles lost or duplicated across ranks";
}

/// Expects f() to throw frnn::error on this rank with a message holding `part`, and every rank
/// to get the very same message.
template <class F>
void expect_collective_error(F&& f, const std::string& part) {
    std::string message;
    try {
        f();
    } catch (const frnn::error& e) {
        message = e.what();
    }
    EXPECT_NE(message.find(part), std::string::npos) << "message '" << message << "' lacks '" << part << "'";
    unsigned long long length = message.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    std::string first(length, ' ');
    if (world_rank() == 0) first = message;
    MPI_Bcast(first.data(), int(length), MPI_CHAR, 0, MPI_COMM_WORLD);
    EXPECT_EQ(message, first) << "ranks threw different errors";
}

}  // namespace frnn::test
