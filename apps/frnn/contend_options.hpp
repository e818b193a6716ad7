// The load options shared by `frnn bench` and `frnn sim`: --contend K (K busy threads in this
// process) and --contend-process K (K busy child processes), exclusive, K in [1, 64]. Giving
// both, or K out of range, is a usage error (exit 2).
#pragma once
#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "frnn/bench/contention.hpp"

namespace frnn::app {

struct contend_args {
    int threads = 0, processes = 0;

    bool any() const { return threads > 0 || processes > 0; }
    int count() const { return threads > 0 ? threads : processes; }
    bench::contention::mode mode() const {
        return threads > 0 ? bench::contention::mode::threads : bench::contention::mode::processes;
    }
    /// The option as typed, for recorded command lines: " --contend 1", or "" without a load.
    std::string flag() const {
        if (!any()) return "";
        return (threads > 0 ? " --contend " : " --contend-process ") + std::to_string(count());
    }
    /// The load, or null without one: its children are forked here.
    std::unique_ptr<bench::contention> make() const {
        return any() ? std::make_unique<bench::contention>(count(), mode()) : nullptr;
    }
};

/// The load and the kernel's scheduling, as reports print them: "1 busy thread in this
/// process; kernel autogroup scheduling: on".
inline std::string load_label(const bench::contention& load) {
    return load.describe() + "; kernel autogroup scheduling: " + bench::autogroup_scheduling();
}

/// Adds --contend and --contend-process to `sub`; `while_what` ends their help text.
inline void add_contend_options(CLI::App* sub, contend_args& a, const std::string& while_what) {
    auto* t = sub->add_option("--contend", a.threads, "K busy threads in this process " + while_what)
                  ->check(CLI::Range(1, 64));
    auto* p = sub->add_option("--contend-process", a.processes, "K busy child processes " + while_what)
                  ->check(CLI::Range(1, 64));
    t->excludes(p);
}

}  // namespace frnn::app
