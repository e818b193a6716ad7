// `frnn validate [CASE...] [--quick]`: runs the simulation's validation cases (frnn/sim/
// validation.hpp), prints every error figure against its tolerance and writes the report.
// Exit codes: 0 every figure within its tolerance, 3 some figure outside it, 1 a failed run or
// bad input, 2 a usage error.
#ifdef FRNN_SIM_AVAILABLE
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/validation.hpp"

namespace frnn::app {
namespace {

struct validate_args {
    std::vector<std::string> cases;
    std::string out = "validation", tolerances, sph;
    int threads = 0;
    bool quick = false, quiet = false;
};

void run_validate(const validate_args& a) {
    sim::validation_options opt;
    opt.quick = a.quick;
    opt.out_dir = a.out;
    opt.threads = a.threads;
    opt.progress = !a.quiet;
    opt.sph_json = a.sph;
    if (!a.tolerances.empty()) {
        std::ifstream in(a.tolerances);
        if (!in) throw error("cannot open tolerances file '" + a.tolerances + "'");
        std::ostringstream text;
        text << in.rdbuf();
        opt.tolerances_json = text.str();
    }
    const sim::validation_report report = sim::validate(a.cases, opt);
    for (const auto& f : report.figures) {
        char tolerance[32] = "-";
        if (f.tolerance) std::snprintf(tolerance, sizeof tolerance, "%.4g", *f.tolerance);
        std::printf("%-10s %-32s %8.4f  tolerance %-8s %s\n", f.case_name.c_str(), f.name.c_str(), f.value, tolerance,
                    !f.tolerance ? "reported" : f.passed() ? "pass" : "FAIL");
    }
    std::printf("report: %s/report.md\n", a.out.c_str());
    if (!report.passed) throw exit_status{3, "some figures are outside their tolerance"};
}

const register_command reg{"validate", [](CLI::App& app) {
    auto args = std::make_shared<validate_args>();
    auto* c = app.add_subcommand("validate", "Validate the simulation against experiments and theory at several "
                                             "resolutions; exit 3 when a figure leaves its tolerance");
    std::string names;
    for (const auto& n : sim::validation_cases()) names += (names.empty() ? "" : "|") + n;
    c->add_option("cases", args->cases, "Cases to run (default: all): " + names)
        ->check(CLI::IsMember(sim::validation_cases()));
    c->add_flag("--quick", args->quick,
                "Coarsest resolution only, with its own tolerances (seconds, where the full run takes minutes)");
    c->add_option("--out", args->out, "Output folder: report.md, errors.json, plots, one folder per run")
        ->capture_default_str();
    c->add_option("--tolerances", args->tolerances,
                  "Tolerances JSON (default: the committed sim/data/validation-tolerances.json)");
    c->add_option("--sph", args->sph,
                  "JSON object of sph keys over the shipped dam break's section, for the dam-break, dam-break-pressure "
                  "and hydrostatic cases, e.g. '{\"alpha\": 0.1}'");
    c->add_option("--threads", args->threads, "Threads (default: all)")->check(CLI::Range(1, 1024));
    c->add_flag("--quiet", args->quiet, "No progress on stderr");
    c->callback([args] { run_validate(*args); });
}};

}  // namespace
}  // namespace frnn::app
#endif
