// What a validation case gives the driver (validation.cpp): its figures and its section of the
// report. One file per case, validate_<case>.cpp.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace frnn::sim {

struct case_context {
    bool quick = false;
    std::string dir;  ///< the case's folder inside the output folder (exists)
    int threads = 0;
    bool progress = true;
    /// The dam break's scene text, the `sph` section of which the WCSPH cases run with: the
    /// shipped one, or with validation_options::sph_json over it.
    std::string dam_break_scene;
};

struct case_output {
    std::vector<std::pair<std::string, double>> figures;  ///< (name, value)
    std::string markdown;  ///< the case's section of report.md (plots relative to the output folder)
};

case_output validate_dam_break(const case_context& context);
case_output validate_dam_break_pressure(const case_context& context);
case_output validate_hydrostatic(const case_context& context);
case_output validate_taylor_green(const case_context& context);

}  // namespace frnn::sim
