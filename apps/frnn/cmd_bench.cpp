// `frnn bench`: the benchmark driver (workloads of bench/README.md, baselines, CSV/Markdown/PNG).
// Built only when the frnn_bench library exists (FRNN_BUILD_BENCHMARKS); otherwise the
// subcommand says how to get it.
#include <iostream>
#include <string>
#include <vector>

#include "command.hpp"
#include "contend_options.hpp"
#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"

#ifdef FRNN_BENCH_AVAILABLE
#include <algorithm>

#include "frnn/bench/report.hpp"
#include "frnn/bench/runner.hpp"
#include "frnn/bench/workloads.hpp"
#endif

namespace frnn::app {
namespace {

struct bench_args {
    std::string workloads = "all";
    std::string sizes, sides;
    std::vector<int> threads{1, 2};
    int repeat = 5;
    std::string backend = "cpu";
    bool baselines = false;
    std::string csv, markdown, plot;
    std::string precision = "float";
    std::string kind = "auto";
    double cell = 0;
    std::string space = "original";
    contend_args contend;
};

template <class V>
std::string join(const std::vector<V>& values) {
    std::string s;
    for (const auto& v : values) s += (s.empty() ? "" : ",") + std::to_string(v);
    return s;
}

#ifdef FRNN_BENCH_AVAILABLE
// The canonical command line of the run, recorded in the report so it can be reproduced.
std::string command_line(const bench_args& a) {
    std::string s = "frnn bench --workload " + a.workloads;
    if (!a.sizes.empty()) s += " --n " + a.sizes;
    if (!a.sides.empty()) s += " --side " + a.sides;
    s += " --threads " + join(a.threads) + " --repeat " + std::to_string(a.repeat);
    if (a.backend != "cpu") s += " --backend " + a.backend;
    if (a.precision != "float") s += " --precision " + a.precision;
    if (a.kind != "auto") s += " --kind " + a.kind;
    if (a.cell != 0) s += " --cell " + std::to_string(a.cell);
    if (a.space != "original") s += " --space " + a.space;
    if (a.baselines) s += " --baselines";
    s += a.contend.flag();
    return s;
}

void run_bench(bench_args a) {
    if (a.backend != "cpu")
        throw error("bench: backend '" + a.backend + "' is not available (only cpu)");
    bench::config cfg;
    cfg.workloads = bench::parse_workload_list(a.workloads);
    bench::parse_sizes(a.sizes, cfg);
    bench::parse_sides(a.sides, cfg);
    std::vector<int> threads;
    for (int t : a.threads)
        if (std::find(threads.begin(), threads.end(), t) == threads.end()) threads.push_back(t);
    cfg.threads = threads;
    cfg.repeat = a.repeat;
    cfg.baselines = a.baselines;
    cfg.double_precision = a.precision == "double";
    cfg.kind = parse_grid_kind(a.kind);
    cfg.cell_factor = a.cell;
    cfg.space = a.space == "sorted" ? index_space::sorted : index_space::original;
    cfg.contend = a.contend.count();
    cfg.contend_mode = a.contend.mode();
    cfg.command = command_line(a);
    cfg.progress = &std::cerr;

    const bench::report rep = bench::run(cfg);
    const std::string markdown = bench::to_markdown(rep);
    std::cout << markdown << std::flush;
    if (!a.csv.empty()) io::write_file_atomically(a.csv, bench::to_csv(rep));
    if (!a.markdown.empty()) io::write_file_atomically(a.markdown, markdown);
    if (!a.plot.empty()) {
        std::string why;
        if (!bench::write_plot(rep, a.plot, why)) std::cerr << "bench: no plot: " << why << "\n";
    }
    if (rep.void_comparison())
        throw error("bench: VOID comparison: methods found different numbers of pairs "
                    "(see the VOID lines above)");
}
#endif

const register_command reg{"bench", [](CLI::App& app) {
    auto args = std::make_shared<bench_args>();
    auto* sub = app.add_subcommand(
        "bench", "Measure build and queries on the workloads of bench/README.md, with baselines");
    sub->add_option("--workload", args->workloads, "W1..W5, W7, W8, all, or a comma list (W1,W2)")
        ->capture_default_str();
    sub->add_option("--n", args->sizes,
                    "point counts replacing the workloads' defaults, a comma list of N (every "
                    "workload) or W=N (one workload, e.g. W1=1000000,W2=1000000); the lattice "
                    "workloads W1, W4, W5 take the lattice count nearest to N");
    sub->add_option("--side", args->sides,
                    "lattice sides, beside or instead of --n: S (every lattice workload) or W=S "
                    "(W1, W4, W5 or W8, e.g. W1=100: 100^3 points)");
    sub->add_option("--threads", args->threads, "thread counts, comma list")
        ->delimiter(',')
        ->capture_default_str();
    sub->add_option("--repeat", args->repeat, "timed runs per phase (median), after a warm-up")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    sub->add_option("--backend", args->backend, "execution backend")->capture_default_str();
    sub->add_flag("--baselines", args->baselines,
                  "also run nanoflann, a textbook cell list and brute force (N <= 32768)");
    sub->add_option("--csv", args->csv, "write the measurements as CSV");
    sub->add_option("--markdown", args->markdown, "write the tables as Markdown");
    sub->add_option("--plot", args->plot, "write a PNG of ns/particle against N (needs gnuplot)");
    sub->add_option("--precision", args->precision, "coordinate type")
        ->check(CLI::IsMember({"float", "double"}))
        ->capture_default_str();
    sub->add_option("--kind", args->kind, "grid kind")
        ->check(CLI::IsMember({"auto", "uniform", "hash", "hashed"}))
        ->capture_default_str();
    sub->add_option("--cell", args->cell, "cell edge as a fraction of r, in [0.25, 1]; 0: default")
        ->capture_default_str();
    sub->add_option("--space", args->space, "numbering of frnn's neighbor lists")
        ->check(CLI::IsMember({"original", "sorted"}))
        ->capture_default_str();
    add_contend_options(sub, args->contend,
                        "during a second run paired with each timed run (table \"Under load\")");
    sub->callback([args] {
#ifdef FRNN_BENCH_AVAILABLE
        run_bench(*args);
#else
        throw error("bench: this frnn was built without the benchmarks (FRNN_BUILD_BENCHMARKS=OFF)");
#endif
    });
}};

}  // namespace
}  // namespace frnn::app
