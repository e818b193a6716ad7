// frnn::sim::validate: the quick dam break against the committed tolerances (report.md,
// errors.json and the plot agree with the returned figures), a figure outside a tolerance
// fails the report (in each case), and bad tolerances or cases are refused, before running where
// they can be.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "frnn/error.hpp"
#include "frnn/sim/impact_pressure.hpp"
#include "frnn/sim/martin_moyce.hpp"
#include "frnn/sim/validation.hpp"
#include "scratch_dir.hpp"
#include "text_lines.hpp"

using namespace frnn::sim;

namespace {

std::string read_text(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

validation_options quick_into(const frnn::test::scratch_dir& dir) {
    validation_options o;
    o.quick = true;
    o.out_dir = dir.string();
    o.threads = 2;
    o.progress = false;
    return o;
}

std::string expect_error(const std::vector<std::string>& cases, const validation_options& o) {
    try {
        validate(cases, o);
    } catch (const frnn::error& e) {
        return e.what();
    }
    ADD_FAILURE() << "validate did not throw";
    return {};
}

// Every figure has a tolerance, is a number and is within its tolerance.
void expect_every_figure_passes(const validation_report& report) {
    for (const auto& f : report.figures) {
        ASSERT_TRUE(f.tolerance.has_value()) << f.name;
        EXPECT_TRUE(f.passed()) << f.name << " = " << f.value << ", tolerance " << *f.tolerance;
        EXPECT_TRUE(std::isfinite(f.value)) << f.name;
    }
    EXPECT_TRUE(report.passed);
}

// Runs quick case `name` with only `figure` held to `tolerance`, below what the coarse run
// reaches: the report fails, and that figure is the one failed in the returned report,
// errors.json and report.md (the others have no tolerance here: reported).
void expect_only_figure_fails(const std::string& name, const std::string& figure, double tolerance) {
    SCOPED_TRACE(name + ": " + figure);
    const frnn::test::scratch_dir dir("validate_tight_" + name);
    validation_options o = quick_into(dir);
    nlohmann::json tolerances;
    tolerances[name]["quick"][figure] = tolerance;
    o.tolerances_json = tolerances.dump();
    const validation_report report = validate({name}, o);
    EXPECT_FALSE(report.passed);
    std::vector<std::string> failed;
    for (const auto& f : report.figures)
        if (!f.passed()) failed.push_back(f.name);
    EXPECT_EQ(failed, std::vector<std::string>{figure});
    const auto doc = nlohmann::json::parse(read_text(dir / "errors.json"));
    EXPECT_FALSE(doc.at("passed").get<bool>());
    for (const auto& f : doc.at("figures"))
        EXPECT_EQ(f.at("passed").get<bool>(), f.at("figure") != figure) << f.dump();
    const std::string row = frnn::test::line_starting(read_text(dir / "report.md"), "| " + name + " | " + figure + " |");
    EXPECT_NE(row.find("| **fail** |"), std::string::npos) << row;
}

}  // namespace

TEST(SimValidation, QuickDamBreakPassesAndWritesItsReport) {
    const frnn::test::scratch_dir dir("validate_quick");
    const validation_report report = validate({"dam-break"}, quick_into(dir));
    // One error per Martin & Moyce series at the coarsest spacing, each with a tolerance.
    ASSERT_EQ(report.figures.size(), martin_moyce().size());
    for (const auto& f : report.figures) {
        EXPECT_EQ(f.case_name, "dam-break");
        ASSERT_TRUE(f.tolerance.has_value()) << f.name;
        EXPECT_GT(f.value, 0) << f.name;
        EXPECT_TRUE(f.passed()) << f.name << " = " << f.value << ", tolerance " << *f.tolerance;
    }
    EXPECT_TRUE(report.passed);

    const auto doc = nlohmann::json::parse(read_text(dir / "errors.json"));
    EXPECT_EQ(doc.at("mode"), "quick");
    EXPECT_TRUE(doc.at("passed").get<bool>());
    ASSERT_EQ(doc.at("figures").size(), report.figures.size());
    const std::string md = read_text(dir / "report.md");
    for (std::size_t k = 0; k < report.figures.size(); ++k) {
        EXPECT_EQ(doc["figures"][k].at("figure"), report.figures[k].name);
        EXPECT_EQ(doc["figures"][k].at("value").get<double>(), report.figures[k].value);
        EXPECT_NE(md.find(report.figures[k].name), std::string::npos) << report.figures[k].name;
    }
    // The run's own summary holds the same errors.
    const auto summary = nlohmann::json::parse(read_text(dir / "dam-break" / "a25" / "summary.json"));
    for (std::size_t k = 0; k < report.figures.size(); ++k)
        EXPECT_EQ(summary.at("martin_moyce").at("series")[k].at("error").get<double>(), report.figures[k].value);
    // The plot is a PNG (gnuplot-nox is in scripts/setup), linked from the report.
    const std::string png = read_text(dir / "dam-break" / "front.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_NE(md.find("](dam-break/front.png)"), std::string::npos);
}

TEST(SimValidation, QuickHydrostaticTankPasses) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    const frnn::test::scratch_dir dir("validate_hydrostatic");
    const validation_report report = validate({"hydrostatic"}, quick_into(dir));
    // Slope, bottom pressure and largest speed, for 2D and 3D, each with a tolerance; the median
    // speed reported beside the largest, below it and above 0 (the tank jitters); and both
    // speeds, reported, of the same tank from a perturbed lattice.
    ASSERT_EQ(report.figures.size(), 12u);
    validation_report held;
    std::map<std::string, double> value;
    for (const auto& f : report.figures) {
        value[f.name] = f.value;
        if (f.name.find("median speed") == std::string::npos && f.name.find("perturbed") == std::string::npos)
            held.figures.push_back(f);
        else
            EXPECT_FALSE(f.tolerance.has_value()) << f.name;
    }
    held.passed = report.passed;
    expect_every_figure_passes(held);
    for (const std::string at : {"2D H/20", "3D H/10"}) {
        ASSERT_EQ(value.count(at + ": median speed over bound"), 1u) << at;
        EXPECT_GT(value[at + ": median speed over bound"], 0) << at;
        EXPECT_LT(value[at + ": median speed over bound"], value[at + ": max speed over bound"]) << at;
        ASSERT_EQ(value.count(at + " perturbed: max speed over bound"), 1u) << at;
        EXPECT_GT(value[at + " perturbed: median speed over bound"], 0) << at;
        EXPECT_LT(value[at + " perturbed: median speed over bound"], value[at + " perturbed: max speed over bound"]) << at;
    }
    const std::string md = read_text(dir / "report.md");
    EXPECT_NE(md.find("| median speed / bound |"), std::string::npos);
    EXPECT_NE(md.find("| 2D | H/20 | lattice |"), std::string::npos);
    EXPECT_NE(md.find("| 3D | H/10 | perturbed |"), std::string::npos);
}

TEST(SimValidation, QuickDamBreakPressurePassesAndWritesItsReport) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    const frnn::test::scratch_dir dir("validate_pressure");
    const validation_report report = validate({"dam-break-pressure"}, quick_into(dir));
    // Per sensor an arrival and a mean error, and a peak (upper sensors) or an impulse (the
    // lowest), each with a tolerance; then, reported, the pressure drop between each pair of
    // Lobovsky et al.'s three sensors, measured and simulated.
    const auto& experiments = impact_pressure_experiments();
    ASSERT_EQ(report.figures.size(), 3 * experiments.size() + 6);
    validation_report held;
    std::map<std::string, double> drops;
    for (const auto& f : report.figures) {
        if (f.name.find("pressure drop") == std::string::npos) {
            held.figures.push_back(f);
            continue;
        }
        EXPECT_FALSE(f.tolerance.has_value()) << f.name;
        drops[f.name] = f.value;
    }
    ASSERT_EQ(held.figures.size(), 3 * experiments.size());
    expect_every_figure_passes(held);
    EXPECT_TRUE(report.passed);
    ASSERT_EQ(drops.size(), 6u);
    // The measured drop is the series' own; the simulated water's pressure falls with height.
    ASSERT_EQ(experiments[1].name, "lobovsky-3mm");
    ASSERT_EQ(experiments[3].name, "lobovsky-80mm");
    EXPECT_DOUBLE_EQ(drops.at("experiment: pressure drop lobovsky-3mm to lobovsky-80mm"),
                     pressure_drop(experiments[1].points, experiments[3].points, 3.5, 5.5));
    for (const auto& [name, value] : drops) {
        if (name.rfind("H/20", 0) == 0) {
            EXPECT_GT(value, 0) << name;
        }
    }
    const std::string md = read_text(dir / "report.md");
    EXPECT_NE(md.find("| H/20 | 800 |"), std::string::npos);
    EXPECT_NE(md.find("](dam-break-pressure/pressure.png)"), std::string::npos);
    const std::string png = read_text(dir / "dam-break-pressure" / "pressure.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    // Every step's sample: a header and one row per step, from T = 0 to T = 6.
    std::istringstream csv(read_text(dir / "dam-break-pressure" / "pressure-H20.csv"));
    std::string line, last;
    std::getline(csv, line);
    EXPECT_EQ(line, "T,buchner-60mm,lobovsky-3mm,lobovsky-30mm,lobovsky-80mm");
    std::getline(csv, line);
    EXPECT_EQ(line.substr(0, 9), "0.000000,");
    std::size_t rows = 1;
    while (std::getline(csv, line)) last = line, ++rows;
    EXPECT_GE(std::stod(last), 6.0);
    EXPECT_GT(rows, 1000u);
}

TEST(SimValidation, QuickTaylorGreenVortexStaysWithinItsTolerance) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    const frnn::test::scratch_dir dir("validate_vortex");
    const validation_report report = validate({"taylor-green"}, quick_into(dir));
    ASSERT_EQ(report.figures.size(), 1u);
    ASSERT_TRUE(report.figures[0].tolerance.has_value());
    EXPECT_TRUE(report.figures[0].passed()) << report.figures[0].value;
    // The energy decays: the error is measured, neither 0 nor a NaN.
    EXPECT_GT(report.figures[0].value, 0);
    EXPECT_TRUE(std::isfinite(report.figures[0].value));
    EXPECT_NE(read_text(dir / "report.md").find("| 50^2 |"), std::string::npos);
}

TEST(SimValidation, FigureOutsideItsToleranceFailsTheReport) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    const frnn::test::scratch_dir dir("validate_tight");
    validation_options o = quick_into(dir);
    // The 2.25 in series held to 1%: the coarse dam break is about 12% off.
    o.tolerances_json = R"({"dam-break": {"quick": {"a/25, a = 2.25 in": 0.01}}})";
    const validation_report report = validate({"dam-break"}, o);
    EXPECT_FALSE(report.passed);
    int failed = 0, reported = 0;
    for (const auto& f : report.figures) {
        failed += !f.passed();
        reported += !f.tolerance;
    }
    EXPECT_EQ(failed, 1);
    EXPECT_EQ(reported, 1);  // the other series has no tolerance here
    EXPECT_FALSE(nlohmann::json::parse(read_text(dir / "errors.json")).at("passed").get<bool>());
    EXPECT_NE(read_text(dir / "report.md").find("**fail**"), std::string::npos);
}

TEST(SimValidation, HydrostaticFigureOutsideItsToleranceFailsTheReport) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    // The coarse 2D tank's bottom pressure is about 1.5% off; held to 0.01%.
    expect_only_figure_fails("hydrostatic", "2D H/20: bottom pressure error", 1e-4);
}

TEST(SimValidation, TaylorGreenFigureOutsideItsToleranceFailsTheReport) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    // The 50^2 vortex's energy is about 7% off; held to 0.1%.
    expect_only_figure_fails("taylor-green", "50^2: energy error", 1e-3);
}

TEST(SimValidation, ToleranceNamingNoFigureIsAnError) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in QuickDamBreakPassesAndWritesItsReport";
#endif
    const frnn::test::scratch_dir dir("validate_typo");
    validation_options o = quick_into(dir);
    o.tolerances_json = R"({"dam-break": {"quick": {"a/25, a = 2.5 in": 0.2}}})";
    EXPECT_NE(expect_error({"dam-break"}, o).find("'dam-break.quick.a/25, a = 2.5 in' names no figure"),
              std::string::npos);
}

TEST(SimValidation, BadInputIsRefusedBeforeRunning) {
    const frnn::test::scratch_dir dir("validate_bad");
    validation_options o = quick_into(dir);
    EXPECT_NE(expect_error({"dam-brake"}, o).find("unknown case 'dam-brake' (cases: dam-break, dam-break-pressure, hydrostatic, taylor-green)"), std::string::npos);
    o.tolerances_json = "{";
    EXPECT_NE(expect_error({}, o).find("not JSON"), std::string::npos);
    o.tolerances_json = R"({"dam-break": {"quick": {"a/25, a = 2.25 in": -1}}})";
    EXPECT_NE(expect_error({}, o).find("'dam-break.quick.a/25, a = 2.25 in' is not a number >= 0: -1"),
              std::string::npos);
    o.tolerances_json = R"({"dam-break": {"quick": 0.1}})";
    EXPECT_NE(expect_error({}, o).find("'dam-break.quick' is not an object"), std::string::npos);
    o.tolerances_json.clear();
    o.out_dir.clear();
    EXPECT_NE(expect_error({}, o).find("no output folder"), std::string::npos);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "nothing ran, nothing was written";
}
