// The validation driver (frnn/sim/validation.hpp): runs the cases, applies the tolerances, and
// writes report.md and errors.json, each whole or not at all.
#include "frnn/sim/validation.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/sim/scene.hpp"
#include "validation_case.hpp"

namespace frnn::sim {

const char* validation_tolerances_json();  // generated from sim/data/validation-tolerances.json

namespace {

using json = nlohmann::json;
using case_runner = std::function<case_output(const case_context&)>;

const std::vector<std::pair<std::string, case_runner>>& registry() {
    static const std::vector<std::pair<std::string, case_runner>> cases = {{"dam-break", validate_dam_break},
                                                                                     {"dam-break-pressure", validate_dam_break_pressure},
                                                                                     {"hydrostatic", validate_hydrostatic},
                                                                                     {"taylor-green", validate_taylor_green}};
    return cases;
}

// The tolerances of `mode` ("full" or "quick") per case and figure, checked for shape.
std::map<std::string, std::map<std::string, double>> read_tolerances(const std::string& text, const std::string& mode) {
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {
        throw error(std::string("validation tolerances: not JSON: ") + e.what());
    }
    if (!doc.is_object()) throw error("validation tolerances: not a JSON object");
    std::map<std::string, std::map<std::string, double>> out;
    for (const auto& [name, entry] : doc.items()) {
        if (name == "about") continue;
        if (!entry.is_object()) throw error("validation tolerances: '" + name + "' is not an object");
        if (!entry.contains(mode)) continue;
        const json& figures = entry[mode];
        if (!figures.is_object()) throw error("validation tolerances: '" + name + "." + mode + "' is not an object");
        for (const auto& [figure, value] : figures.items()) {
            if (!value.is_number() || !(value.get<double>() >= 0))
                throw error("validation tolerances: '" + name + "." + mode + "." + figure +
                            "' is not a number >= 0: " + value.dump());
            out[name][figure] = value.get<double>();
        }
    }
    return out;
}

// The shipped dam break's scene text, with the keys of sph_json (a JSON object) laid over its
// `sph` section; checked by the scene parser, whose error names a bad key or value.
std::string dam_break_scene(const std::string& sph_json) {
    const std::string shipped = builtin_scene_text("dam-break");
    if (sph_json.empty()) return shipped;
    json over;
    try {
        over = json::parse(sph_json);
    } catch (const json::exception& e) {
        throw error(std::string("validate --sph: not JSON: ") + e.what());
    }
    if (!over.is_object()) throw error("validate --sph: expected a JSON object of sph keys, got " + over.dump());
    json scene = json::parse(shipped);
    scene["sph"].update(over);
    const std::string text = scene.dump();
    (void)parse_scene(text, "validate --sph");
    return text;
}

std::string utc_now() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
    return text;
}

std::string figures_table(const std::vector<validation_figure>& figures) {
    std::string md = "| case | figure | value | tolerance | result |\n| --- | --- | ---: | ---: | --- |\n";
    for (const auto& f : figures) {
        char row[320], tolerance[32] = "-";
        if (f.tolerance) std::snprintf(tolerance, sizeof tolerance, "%.4g", *f.tolerance);
        std::snprintf(row, sizeof row, "| %s | %s | %.4g | %s | %s |\n", f.case_name.c_str(), f.name.c_str(), f.value,
                      tolerance, !f.tolerance ? "reported" : f.passed() ? "pass" : "**fail**");
        md += row;
    }
    return md;
}

}  // namespace

std::vector<std::string> validation_cases() {
    std::vector<std::string> names;
    for (const auto& [name, runner] : registry()) names.push_back(name);
    return names;
}

validation_report validate(const std::vector<std::string>& cases, const validation_options& options) {
    if (options.out_dir.empty()) throw error("validate: no output folder given");
    const std::vector<std::string> chosen = cases.empty() ? validation_cases() : cases;
    std::vector<std::pair<std::string, case_runner>> runs;
    for (const auto& name : chosen) {
        auto it = registry().begin();
        while (it != registry().end() && it->first != name) ++it;
        if (it == registry().end()) {
            std::string known;
            for (const auto& n : validation_cases()) known += (known.empty() ? "" : ", ") + n;
            throw error("validate: unknown case '" + name + "' (cases: " + known + ")");
        }
        runs.push_back(*it);
    }
    const std::string mode = options.quick ? "quick" : "full";
    const std::string dam_break = dam_break_scene(options.sph_json);
    const auto tolerances = read_tolerances(
        options.tolerances_json.empty() ? std::string(validation_tolerances_json()) : options.tolerances_json, mode);

    std::filesystem::create_directories(options.out_dir);
    validation_report report;
    std::string sections;
    for (const auto& [name, runner] : runs) {
        case_context context;
        context.quick = options.quick;
        context.dir = options.out_dir + "/" + name;
        context.threads = options.threads;
        context.progress = options.progress;
        context.dam_break_scene = dam_break;
        std::filesystem::create_directories(context.dir);
        const case_output out = runner(context);
        sections += out.markdown;
        const auto found = tolerances.find(name);
        std::set<std::string> names;
        for (const auto& [figure, value] : out.figures) {
            validation_figure f{name, figure, value, std::nullopt};
            if (found != tolerances.end())
                if (auto t = found->second.find(figure); t != found->second.end()) f.tolerance = t->second;
            report.passed = report.passed && f.passed();
            report.figures.push_back(f);
            names.insert(figure);
        }
        if (found != tolerances.end())
            for (const auto& [figure, tolerance] : found->second)
                if (!names.count(figure))
                    throw error("validation tolerances: '" + name + "." + mode + "." + figure +
                                "' names no figure of the case");
    }

    json doc;
    doc["mode"] = mode;
    doc["passed"] = report.passed;
    doc["sph"] = options.sph_json.empty() ? json(nullptr) : json::parse(options.sph_json);
    doc["figures"] = json::array();
    for (const auto& f : report.figures)
        doc["figures"].push_back({{"case", f.case_name},
                                  {"figure", f.name},
                                  {"value", f.value},
                                  {"tolerance", f.tolerance ? json(*f.tolerance) : json(nullptr)},
                                  {"passed", f.passed()}});
    io::write_file_atomically(options.out_dir + "/errors.json", doc.dump(2) + "\n");

    std::string md = "# frnn validate (" + mode + ")\n\nRun " + utc_now() + ". Every figure and its tolerance " +
                     "(sim/data/validation-tolerances.json; a figure passes when it is at most its tolerance):\n\n";
    if (!options.sph_json.empty())
        md += "The `sph` section of the dam-break, dam-break-pressure and hydrostatic cases: the shipped dam break's with `" +
              json::parse(options.sph_json).dump() + "` over it (`--sph`).\n\n";
    md += figures_table(report.figures);
    md += std::string("\n") + (report.passed ? "All figures pass.\n\n" : "Some figures are outside their tolerance.\n\n");
    io::write_file_atomically(options.out_dir + "/report.md", md + sections);
    return report;
}

}  // namespace frnn::sim
