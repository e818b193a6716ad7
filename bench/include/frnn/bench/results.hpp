// What a benchmark run produced: one row per (workload, size, threads, method, phase), with its
// median under load when there was one, the memory of each method, and the notes (skipped
// baselines, VOID comparisons). Plain values.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace frnn::bench {

/// Methods and phases, in the order reports list them.
inline const std::vector<std::string> methods{"frnn", "nanoflann", "cell-list", "brute", "lammps"};
/// Half-list phases: those of the md workload (W8), and LAMMPS's neighbor build.
inline const std::vector<std::string> phases{
    "build", "count", "list", "build+list", "update",
    "half", "half sorted-space", "half by-index", "build+half by-index",  // md workloads
    "build+half",                                                         // LAMMPS
};

struct row {
    std::string workload;  ///< "W1" .. "W5", "W8"
    std::size_t n = 0;     ///< number of points
    int threads = 1;
    std::string method;    ///< one of `methods`
    std::string phase;     ///< one of `phases`
    double ms = 0;         ///< median
    double ns_per_particle = 0;
    std::optional<std::uint64_t> pairs;  ///< directed pairs found; none for build and update
    std::optional<double> contended_ms;  ///< median under load (--contend); `ms` stays the quiet one
    int load_pairs = 0;                  ///< quiet/contended pairs of runs behind the two medians
};

struct memory_row {
    std::string workload;
    std::size_t n = 0;
    int threads = 1;
    std::string method;
    double structure_bytes_per_particle = 0;  ///< the search structure itself
    double peak_rss_mib = 0;  ///< peak resident memory while this method ran
};

/// One workload at one size: what the report prints under one heading.
struct case_info {
    std::string workload, name;
    std::size_t side = 0;  ///< side of a lattice workload's lattice; 0 for the others
    std::size_t n = 0;     ///< points
    int dim = 3;
    double radius = 0;
    std::vector<std::string> notes;  ///< skipped baselines and the like
    std::vector<std::string> voids;  ///< VOID messages: pair counts that disagree
};

struct report {
    std::string command;      ///< the command that reproduces the run
    std::string machine;      ///< CPU model and hardware threads
    std::string build;        ///< compiler and build flavour
    std::string settings;     ///< precision, grid kind, index space, repetitions
    std::string load;         ///< the load of --contend ("1 busy thread in this process"); empty: none
    std::string autogroup;    ///< the kernel's autogroup scheduling under load: on, off, unknown
    bool rss_per_method = true;  ///< false: peak RSS is the process's peak so far
    std::vector<case_info> cases;
    std::vector<row> rows;
    std::vector<memory_row> memory;

    bool void_comparison() const;
};

/// VOID messages for the rows of one case: every row that reports pairs must report the same
/// number. Empty when they agree.
std::vector<std::string> disagreements(const std::vector<row>& rows, const std::string& workload,
                                       std::size_t n);

/// Rows matching the key, or nullptr.
const row* find_row(const std::vector<row>& rows, const std::string& workload, std::size_t n,
                    int threads, const std::string& method, const std::string& phase);

}  // namespace frnn::bench
