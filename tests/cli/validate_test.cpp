// `frnn validate`: exit 0 and a line per figure when every figure is within its tolerance, 3
// when one is not (with the committed tolerances replaced by --tolerances; in each case), 2 for
// an unknown case, 1 for a tolerances file that cannot be read or a bad --sph.
#include "cli/run_tool.hpp"

#ifdef FRNN_TOOL_HAS_SIM
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "text_lines.hpp"

namespace frnn::test {
namespace {

TEST(cli_validate, quick_passes_then_fails_a_tighter_tolerance) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in SimValidation";
#endif
    const auto dir = fresh_dir();
    const tool_result pass = run_tool(dir, "validate --quick --quiet --threads 2 --out ok");
    ASSERT_EQ(pass.code, 0) << pass.err;
    EXPECT_NE(line_starting(pass.out, "dam-break  a/25, a = 2.25 in").find(" pass"), std::string::npos) << pass.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "ok" / "report.md"));

    std::ofstream(dir / "tight.json") << R"({"dam-break": {"quick": {"a/25, a = 1.125 in": 0.001}}})";
    const tool_result fail = run_tool(dir, "validate dam-break --quick --quiet --threads 2 --out tight "
                                           "--tolerances tight.json");
    EXPECT_EQ(fail.code, 3) << fail.err;
    EXPECT_NE(line_starting(fail.out, "dam-break  a/25, a = 1.125 in").find("FAIL"), std::string::npos) << fail.out;
    EXPECT_NE(fail.err.find("some figures are outside their tolerance"), std::string::npos) << fail.err;
}

// The same for the other cases: one figure held below what the coarse run reaches fails the
// run (exit 3), and its line is the one marked FAIL (the others have no tolerance here).
TEST(cli_validate, tighter_hydrostatic_and_taylor_green_tolerances_fail) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in SimValidation";
#endif
    const auto dir = fresh_dir();
    struct tightened {
        std::string name, figure;
        double tolerance;
    };
    // The coarse 2D tank's bottom pressure is about 1.5% off, the 50^2 vortex's energy about 7%.
    for (const tightened& t : {tightened{"hydrostatic", "2D H/20: bottom pressure error", 1e-4},
                               tightened{"taylor-green", "50^2: energy error", 1e-3}}) {
        SCOPED_TRACE(t.name);
        nlohmann::json tolerances;
        tolerances[t.name]["quick"][t.figure] = t.tolerance;
        std::ofstream(dir / "tight.json") << tolerances.dump();
        const tool_result fail =
            run_tool(dir, "validate " + t.name + " --quick --quiet --threads 2 --out tight --tolerances tight.json");
        EXPECT_EQ(fail.code, 3) << fail.err;
        EXPECT_NE(line_starting(fail.out, t.name + " " + t.figure).find("FAIL"), std::string::npos) << fail.out;
        EXPECT_EQ(fail.out.find("FAIL"), fail.out.rfind("FAIL")) << "one line marked FAIL:\n" << fail.out;
        EXPECT_NE(fail.err.find("some figures are outside their tolerance"), std::string::npos) << fail.err;
    }
}

// --sph lays keys over the shipped dam break's sph section: the tank runs with them, and the
// report and errors.json say so. A bad key or value stops before anything is written.
TEST(cli_validate, sph_keys_over_the_shipped_section) {
    const auto dir = fresh_dir();
    for (const char* bad : {R"('{"alpah": 1}')", R"('{"alpha": 20}')", "'[1]'", "'{'"}) {
        SCOPED_TRACE(bad);
        const tool_result r = run_tool(dir, std::string("validate hydrostatic --quick --quiet --out bad --sph ") + bad);
        EXPECT_EQ(r.code, 1);
        EXPECT_NE(r.err.find("validate --sph: "), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
    }
    const tool_result misspelled = run_tool(dir, R"(validate hydrostatic --quick --quiet --out bad --sph '{"alpah": 1}')");
    EXPECT_NE(misspelled.err.find("key 'sph.alpah'"), std::string::npos) << misspelled.err;
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "the sanitizer tree runs the quick case once, in SimValidation";
#endif
    const std::string figure = "2D H/20: max speed over bound";
    auto speed = [&](const std::string& out) {
        const auto doc = nlohmann::json::parse(std::ifstream(dir / out / "errors.json"));
        for (const auto& f : doc["figures"])
            if (f["figure"] == figure) return f["value"].get<double>();
        ADD_FAILURE() << "no figure '" << figure << "' in " << out;
        return 0.0;
    };
    const tool_result shipped = run_tool(dir, "validate hydrostatic --quick --quiet --threads 2 --out shipped");
    ASSERT_EQ(shipped.code, 0) << shipped.err;
    const tool_result less = run_tool(dir, R"(validate hydrostatic --quick --quiet --threads 2 --out less --sph '{"alpha": 0.1}')");
    ASSERT_TRUE(less.code == 0 || less.code == 3) << less.err;
    // A third of the artificial viscosity lets the coarse tank move faster.
    EXPECT_GT(speed("less"), 1.5 * speed("shipped"));
    const auto doc = nlohmann::json::parse(std::ifstream(dir / "less" / "errors.json"));
    EXPECT_EQ(doc["sph"], nlohmann::json::parse(R"({"alpha": 0.1})"));
    EXPECT_TRUE(nlohmann::json::parse(std::ifstream(dir / "shipped" / "errors.json"))["sph"].is_null());
    std::ifstream report(dir / "less" / "report.md");
    const std::string text((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("the shipped dam break's with `{\"alpha\":0.1}` over it"), std::string::npos) << text;
}

TEST(cli_validate, unknown_case_and_missing_tolerances) {
    const auto dir = fresh_dir();
    const tool_result unknown = run_tool(dir, "validate dam-brake --quick --out out");
    EXPECT_EQ(unknown.code, 2);
    EXPECT_NE(unknown.err.find("dam-brake"), std::string::npos) << unknown.err;
    const tool_result missing = run_tool(dir, "validate --quick --out out --tolerances nowhere.json");
    EXPECT_EQ(missing.code, 1);
    EXPECT_NE(missing.err.find("cannot open tolerances file 'nowhere.json'"), std::string::npos) << missing.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace frnn::test

#endif  // FRNN_TOOL_HAS_SIM
