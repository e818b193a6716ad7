// The benchmark runner behind `frnn bench`: for each workload and size it generates the points,
// measures frnn's phases (build, count, list, build+list, update) at each thread count and, on
// request, the baselines in the same process (each run paired with one under load on
// request), then checks that every method found the same number of pairs. Time: dominated by the workloads (up to 4 M points) and, for N <= 32,768,
// brute force. Not thread-safe: it resets the process's peak-RSS counter.
#pragma once
#include <cstddef>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "frnn/bench/contention.hpp"
#include "frnn/bench/results.hpp"
#include "frnn/options.hpp"

namespace frnn::bench {

struct config {
    std::vector<std::string> workloads{"W1", "W2", "W3", "W4", "W5", "W8"};
    /// Point counts for every workload (--n; a lattice workload takes its nearest lattice
    /// count); empty, and no `sides` either: each workload's default sizes.
    std::vector<std::size_t> sizes;
    /// Point counts for one workload ("W2" -> {1000000}); they win over `sizes` and `sides`.
    std::map<std::string, std::vector<std::size_t>> workload_sizes;
    /// Lattice sides for every lattice workload (--side), beside `sizes`.
    std::vector<std::size_t> sides;
    /// Lattice sides for one lattice workload ("W1" -> {100}), beside `workload_sizes`.
    std::map<std::string, std::vector<std::size_t>> workload_sides;
    std::vector<int> threads{1, 2};  ///< frnn grid threads (and nanoflann's query threads)
    int repeat = 5;                  ///< timed runs per phase, after one warm-up
    bool baselines = false;
    bool double_precision = false;   ///< double coordinates instead of float
    grid_kind kind = grid_kind::automatic;
    double cell_factor = 0;          ///< cell edge as a fraction of r; 0: the grid's default
    index_space space = index_space::original;  ///< numbering of frnn's neighbor lists
    /// Busy threads or child processes (1 to 64) during paired runs under load (see measure());
    /// 0: no load, and no contended runs.
    int contend = 0;
    contention::mode contend_mode = contention::mode::threads;
    std::string command;             ///< recorded in the report
    std::ostream* progress = nullptr;  ///< one line per step, and the VOID lines
};

/// Parses the --n text into `cfg`: a comma list of point counts for every workload
/// ("32768,262144") and/or for one workload ("W1=1000000,W2=1000000"). Throws frnn::error for
/// anything else.
void parse_sizes(std::string_view text, config& cfg);

/// Parses the --side text into `cfg`: lattice sides, for every lattice workload ("64") and/or
/// for one ("W1=100"). Throws frnn::error for anything else, or a side for W2 or W3.
void parse_sides(std::string_view text, config& cfg);

/// The point counts `cfg` asks of workload `id`, as generated (lattices rounded), in order,
/// without repeats: those named for `id` (--n W=N, --side W=S), else those for every workload
/// (--n N, and --side S for a lattice workload), else its defaults. Throws frnn::error for a
/// count of 0 or beyond 2^32 - 2.
std::vector<std::size_t> sizes_for(const config& cfg, const std::string& id);

/// Runs everything `cfg` asks for; throws frnn::error for bad settings or failures.
report run(const config& cfg);

}  // namespace frnn::bench
