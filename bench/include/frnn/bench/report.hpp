// Turns a benchmark report into text: the CSV (one row per measurement, header
// `workload,n,threads,method,phase,ms,ns_per_particle,pairs,contended_ms,load_pairs`) and the
// Markdown tables (the rows, the medians under load, frnn's ratio to each baseline, thread
// scaling, memory, notes). O(rows^2) at most, for a few hundred rows. Thread-safe: pure
// functions.
#pragma once
#include <string>

#include "frnn/bench/results.hpp"

namespace frnn::bench {

inline constexpr const char* csv_header =
    "workload,n,threads,method,phase,ms,ns_per_particle,pairs,contended_ms,load_pairs";

/// The CSV: the header, then the rows case by case. `pairs` is empty for build and update
/// (they find no pairs); `contended_ms` (median under load) and `load_pairs` (quiet/contended
/// pairs of runs) are empty without a load, and `ms` is always the quiet median. A comparison whose pair counts differ is followed by a line
/// `# VOID ...` (a comment line: CSV readers that skip '#' lines still parse the file).
std::string to_csv(const report& rep);

/// The same as Markdown tables, plus the table "Under load" (with a load), ratios, thread
/// scaling and memory.
std::string to_markdown(const report& rep);

/// Writes a PNG of ns/particle (build+list) against N, log scales, one panel per workload and
/// one line per method and thread count, with gnuplot. Returns false, with the reason in
/// `why`, when gnuplot is not installed; throws frnn::error when gnuplot fails. Atomic.
bool write_plot(const report& rep, const std::string& png_path, std::string& why);

}  // namespace frnn::bench
