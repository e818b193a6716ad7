// Validation of the simulation against experiments and theory, at several resolutions: each
// case runs its scenes, computes its error figures, and the figures are checked against the
// committed tolerances (sim/data/validation-tolerances.json): the goals for the full run, the
// coarsest resolution's measured error plus one percentage point for the quick run. What
// `frnn validate` runs; its report (report.md with PNG plots, errors.json) goes to a folder.
//
// Cases: "dam-break" (2D WCSPH, the surge front against both series of Martin & Moyce 1952,
// particle spacing a/25, a/50, a/100 and a/200; quick: a/25); "dam-break-pressure" (the
// pressure on the far wall against Buchner 2002 and Lobovsky et al. 2014, 2D at H/50, H/100,
// H/200 and 3D at H/40; quick: 2D H/20); "hydrostatic" (WCSPH water at rest in
// a tank: pressure slope, bottom pressure and largest speed after settling, 2D at H/20, H/40,
// H/80 and 3D at H/10, H/15, H/20; quick: H/20 and H/10); "taylor-green" (the 2D vortex at
// Re = 100 in a periodic box, WCSPH with the laminar viscosity: the kinetic energy's decay
// against exp(-16 pi^2 nu t), 50^2, 100^2, 200^2 particles; quick: 50^2).
// Thread safety: one validation per output folder; runs use `threads` threads of frnn's pool.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace frnn::sim {

struct validation_options {
    bool quick = false;           ///< the coarsest resolution of each case, with its tolerances
    std::string out_dir;          ///< report.md, errors.json, plots and one folder per run
    std::string tolerances_json;  ///< empty: the committed tolerances
    int threads = 0;              ///< 0: all hardware threads
    bool progress = true;         ///< one line per run on stderr
    /// A JSON object of `sph` keys laid over the shipped dam break's section, which the
    /// dam-break, dam-break-pressure and hydrostatic cases run with (empty: that section as
    /// shipped); taylor-green has its own. A bad key or value is an error naming it.
    std::string sph_json;
};

/// One error figure of a case, e.g. ("dam-break", "a/100, a = 2.25 in").
struct validation_figure {
    std::string case_name, name;
    double value = 0;
    std::optional<double> tolerance;  ///< passes when value <= tolerance; none: reported only
    bool passed() const { return !tolerance || value <= *tolerance; }
};

struct validation_report {
    std::vector<validation_figure> figures;
    bool passed = true;  ///< every figure passed
};

/// The cases, in the order they run when none is named.
std::vector<std::string> validation_cases();

/// Runs `cases` (all when empty) and writes the report into options.out_dir (created). Throws
/// frnn::error for an unknown case, a tolerances document that is not as described above (a
/// tolerance naming no figure included), or a failed run. Figures outside their tolerance do
/// not throw: the report says so.
validation_report validate(const std::vector<std::string>& cases, const validation_options& options);

}  // namespace frnn::sim
