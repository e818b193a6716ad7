// The dam-break validation case: the shipped dam break in 2D with WCSPH at particle spacings
// a/25, a/50, a/100 and a/200 (a the column width), its surge front against both series of
// Martin & Moyce (1952). Two questions, kept apart. Verification: the self-convergence D of
// each spacing against the next (front_difference), the ratio of successive D (below 1 when
// D falls with each halving; below 2^-1/2 when the observed order log2 of its inverse is at
// least 1/2) and that order. Validation: each series' error at each spacing (front_error),
// its signed error per measured point, and, when the observed order over the finest three
// spacings lies in [1/2, 3], the error of the Richardson-extrapolated front.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/io/gnuplot.hpp"
#include "frnn/sim/martin_moyce.hpp"
#include "frnn/sim/run.hpp"
#include "frnn/sim/scene.hpp"
#include "validation_case.hpp"

namespace frnn::sim {

namespace {

std::string series_label(const front_series& s) {
    char text[32];
    std::snprintf(text, sizeof text, "a = %g in", s.a_inches);
    return text;
}

using front_record = std::vector<std::pair<double, double>>;

// Z against T: the measured points of both series, one line per spacing and the extrapolated
// front (when there is one).
std::string front_plot(const std::vector<int>& spacings, const std::vector<run_result>& runs,
                       const front_record& extrapolated) {
    std::string s = "set termoption noenhanced\nset xlabel 'T = t sqrt(2g/a)'\nset ylabel 'Z = front / a'\nset grid\nset key left top\n";
    s += "set title 'Dam break 2D (WCSPH): surge front against Martin & Moyce (1952)'\n";
    s += "set xrange [0:" + std::to_string(front_error_t_hi + 0.2) + "]\n";
    std::string plot;
    int block = 0;
    auto add_block = [&](const std::vector<std::pair<double, double>>& points, const std::string& style,
                         const std::string& title) {
        const std::string name = "$d" + std::to_string(block++);
        s += io::gnuplot_data_block(name, points);
        plot += std::string(plot.empty() ? "plot " : ", ") + name + " using 1:2 " + style + " title " +
                io::gnuplot_quoted(title);
    };
    const char* point_styles[] = {"with points pt 7 ps 1.2 lc rgb '#000000'", "with points pt 5 ps 1.2 lc rgb '#7f7f7f'"};
    int k = 0;
    for (const auto& series : martin_moyce())
        add_block(series.points, point_styles[k++ % 2], "Martin & Moyce, " + series_label(series));
    const char* colours[] = {"#2471a3", "#229954", "#c0392b", "#7d3c98"};
    for (std::size_t r = 0; r < runs.size(); ++r)
        add_block(runs[r].front, std::string("with lines lw 2 lc rgb '") + colours[r % 4] + "'",
                  "frnn, spacing a/" + std::to_string(spacings[r]));
    if (!extrapolated.empty())
        add_block(extrapolated, "with lines lw 2 dt 2 lc rgb '#000000'", "frnn, extrapolated to zero spacing");
    return s + plot + "\n";
}

// Per series, the signed error (Z_sim - Z) / Z at each measured point with T in the error's
// range, one column per spacing (and the extrapolated front): positive where frnn's front leads.
std::string signed_error_tables(const std::vector<int>& spacings, const std::vector<run_result>& runs,
                                const front_record& extrapolated) {
    std::string md;
    for (const auto& s : martin_moyce()) {
        md += "Signed error against the " + series_label(s) + " series, (Z_sim - Z) / Z:\n\n| T | Z measured |";
        for (int k : spacings) md += " a/" + std::to_string(k) + " |";
        if (!extrapolated.empty()) md += " extrapolated |";
        md += "\n| ---: | ---: |";
        for (std::size_t r = 0; r < runs.size() + (extrapolated.empty() ? 0 : 1); ++r) md += " ---: |";
        md += "\n";
        std::vector<std::vector<std::pair<double, double>>> columns;
        for (const auto& r : runs) columns.push_back(signed_front_errors(r.front, s));
        if (!extrapolated.empty()) columns.push_back(signed_front_errors(extrapolated, s));
        std::size_t row = 0;
        for (const auto& [T, Z] : s.points) {
            if (T < front_error_t_lo || T > front_error_t_hi) continue;
            char cell[64];
            std::snprintf(cell, sizeof cell, "| %.2f | %.2f |", T, Z);
            md += cell;
            for (const auto& c : columns) {
                std::snprintf(cell, sizeof cell, " %+.1f%% |", 100 * c[row].second);
                md += cell;
            }
            md += "\n";
            ++row;
        }
        md += "\n";
    }
    return md;
}

}  // namespace

case_output validate_dam_break(const case_context& context) {
    const std::vector<int> spacings = context.quick ? std::vector<int>{25} : std::vector<int>{25, 50, 100, 200};
    const scene base = parse_scene(context.dam_break_scene, "dam-break");
    const double g = std::abs(base.gravity[1]);
    std::vector<run_result> runs;
    for (int k : spacings) {
        scene_overrides o;
        o.solver = solver_kind::sph;
        o.dim = 2;
        o.particles = std::size_t(2 * k * k);  // a column a wide and 2a high at spacing a/k
        o.duration = (front_error_t_hi + 0.1) / std::sqrt(2 * g / base.front.a);
        run_options opt;
        opt.out_dir = context.dir + "/a" + std::to_string(k);
        opt.threads = context.threads;
        opt.write_frames = false;
        opt.progress = false;
        opt.print_table = false;
        if (context.progress) std::fprintf(stderr, "dam-break: spacing a/%d, %zu particles\n", k, *o.particles);
        runs.push_back(run(context.dam_break_scene, "dam-break", o, opt));
        if (runs.back().front_errors.size() != martin_moyce().size())
            throw error("dam-break at a/" + std::to_string(k) + ": the run did not record the front up to T = " +
                        std::to_string(front_error_t_hi));
    }

    case_output out;
    const auto& series = martin_moyce();
    for (std::size_t r = 0; r < runs.size(); ++r)
        for (std::size_t s = 0; s < series.size(); ++s)
            out.figures.emplace_back("a/" + std::to_string(spacings[r]) + ", " + series_label(series[s]),
                                     runs[r].front_errors[s]);
    const auto pair_name = [&](std::size_t r) {
        return "D(a/" + std::to_string(spacings[r]) + ", a/" + std::to_string(spacings[r + 1]) + ")";
    };
    std::vector<double> difference;  // D(a/k, a/2k) of each spacing against the next
    for (std::size_t r = 0; r + 1 < runs.size(); ++r) {
        difference.push_back(front_difference(runs[r].front, runs[r + 1].front));
        out.figures.emplace_back(pair_name(r), difference.back());
    }
    double order = 0;  // over the finest three spacings
    for (std::size_t r = 0; r + 1 < difference.size(); ++r) {
        out.figures.emplace_back(pair_name(r + 1) + " over " + pair_name(r), difference[r + 1] / difference[r]);
        order = std::log2(difference[r] / difference[r + 1]);
        out.figures.emplace_back("observed order, a/" + std::to_string(spacings[r]) + " to a/" +
                                     std::to_string(spacings[r + 2]),
                                 order);
    }
    // Richardson's extrapolation only where the order says the fronts are in their asymptotic range.
    front_record extrapolated;
    if (difference.size() >= 2 && order >= 0.5 && order <= 3) {
        extrapolated = richardson_front(runs[runs.size() - 2].front, runs.back().front, order);
        for (std::size_t s = 0; s < series.size(); ++s)
            out.figures.emplace_back("extrapolated, " + series_label(series[s]), front_error(extrapolated, series[s]));
    }

    std::string why;
    const bool plotted =
        io::draw_with_gnuplot(front_plot(spacings, runs, extrapolated), 900, 560, context.dir + "/front.png", why);
    std::string& md = out.markdown;
    md += "## Dam break 2D (WCSPH) against Martin & Moyce (1952)\n\n";
    md += "The shipped dam-break scene in 2D with WCSPH: a column a wide and 2a high collapses along a tank 8a "
          "long. The error is the mean of |Z_sim - Z| / Z over each measured series' points with T in [";
    char range[64];
    std::snprintf(range, sizeof range, "%g, %g", front_error_t_lo, front_error_t_hi);
    md += std::string(range) + "] (frnn/sim/martin_moyce.hpp).\n\n";
    md += plotted ? "![surge front](dam-break/front.png)\n\n" : "(no plot: " + why + ")\n\n";
    md += "| spacing | particles | steps | wall s |";
    for (const auto& s : series) md += " error, " + series_label(s) + " |";
    md += "\n| --- | ---: | ---: | ---: |";
    for (std::size_t s = 0; s < series.size(); ++s) md += " ---: |";
    md += "\n";
    for (std::size_t r = 0; r < runs.size(); ++r) {
        char row[160];
        std::snprintf(row, sizeof row, "| a/%d | %zu | %llu | %.1f |", spacings[r], runs[r].particles,
                      (unsigned long long)runs[r].steps, runs[r].wall_seconds);
        md += row;
        for (double e : runs[r].front_errors) {
            std::snprintf(row, sizeof row, " %.1f%% |", 100 * e);
            md += row;
        }
        md += "\n";
    }
    md += "\n";
    if (!difference.empty()) {
        md += "Self-convergence: D(h1, h2), the mean of |Z_h1 - Z_h2| / Z_h2 over T = 0.5, 0.52, ..., 3:";
        for (std::size_t r = 0; r < difference.size(); ++r) {
            char part[96];
            std::snprintf(part, sizeof part, "%s D(a/%d, a/%d) = %.2f%%", r ? "," : "", spacings[r], spacings[r + 1],
                          100 * difference[r]);
            md += part;
        }
        md += ".\n\n";
    }
    if (!extrapolated.empty()) {
        char line[200];
        std::snprintf(line, sizeof line,
                      "The observed order over the finest three spacings is %.2f, in [0.5, 3]: the front extrapolated "
                      "to zero spacing (Richardson, from the two finest) is the dashed line.\n\n",
                      order);
        md += line;
    }
    md += signed_error_tables(spacings, runs, extrapolated);
    return out;
}

}  // namespace frnn::sim
