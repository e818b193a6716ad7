// The benchmark runner behind `frnn bench`: for each workload and size it generates the points,
// measures frnn's phases (build, count, list, build+list, update) at each thread count and, on
// request, the baselines in the same process, then checks that every method found the same
// number of pairs. Time: dominated by the workloads (up to 4 M points) and, for N <= 32,768,
// brute force. Not thread-safe: it resets the process's peak-RSS counter.
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "frnn/bench/results.hpp"
#include "frnn/options.hpp"

namespace frnn::bench {

struct config {
    std::vector<std::string> workloads{"W1", "W2", "W3", "W4", "W5"};
    /// Sizes applied to every workload (lattice side for W1/W4/W5, points for W2/W3);
    /// empty: each workload's default sizes.
    std::vector<std::size_t> sizes;
    std::vector<int> threads{1, 2};  ///< frnn grid threads (and nanoflann's query threads)
    int repeat = 5;                  ///< timed runs per phase, after one warm-up
    bool baselines = false;
    bool double_precision = false;   ///< double coordinates instead of float
    grid_kind kind = grid_kind::automatic;
    double cell_factor = 0;          ///< cell edge as a fraction of r; 0: the grid's default
    index_space space = index_space::original;  ///< numbering of frnn's neighbor lists
    std::string command;             ///< recorded in the report
    std::ostream* progress = nullptr;  ///< one line per step, and the VOID lines
};

/// Runs everything `cfg` asks for; throws frnn::error for bad settings or failures.
report run(const config& cfg);

}  // namespace frnn::bench
