// The dam-break-pressure validation case: a water column 2H long and H high (H = 0.3 m) at one
// end of a tank 5.366H long and 3H high collapses, in 2D with WCSPH and the shipped dam break's
// parameters, and hits the far wall; the pressure at the four sensors of Buchner (2002) and
// Lobovsky et al. (2014) on that wall (frnn/sim/impact_pressure.hpp), sampled every step, to
// T = t sqrt(g/H) = 6. Particle spacing H/50, H/100, H/200, and in 3D (Lobovsky et al.'s tank,
// 0.5H wide) H/40; quick: 2D H/20 only. Figures per run:
// each sensor's arrival error and mean error after impact, the upper sensors' peak error, the
// lowest sensor's impulse error; in the full run the self-convergence D of each spacing against
// the next and the observed order; the mean pressure drop between Lobovsky et al.'s sensors,
// measured and simulated, beside the static head (reported).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frnn/io/atomic_file.hpp"
#include "frnn/io/gnuplot.hpp"
#include "frnn/sim/impact_pressure.hpp"
#include "frnn/sim/profiler.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"
#include "validation_case.hpp"

namespace frnn::sim {

namespace {

constexpr double H = 0.3, g = 9.81, tank_height = 3.0;
constexpr double t_end = 6.0;            // T of the run's end
constexpr double error_t_hi = 5.5;       // the mean error's window ends before the second impact
constexpr double peak_window = 1.0;      // the peak or plateau: within this after the arrival
constexpr double impulse_window = 0.5;   // the first impact at the lowest sensor: this long
constexpr double convergence_t_lo = 2.0; // D's window: from before the first arrival
constexpr double drop_t_lo = 3.5;        // the pressure drops' window: after the first impact's
                                         // spike at every sensor (the last arrives at T = 2.9)
constexpr double width_3d = 0.5;         // Lobovsky et al.'s tank is 150 mm wide (over H)
constexpr int spacing_3d = 40;           // the 3D run's spacing H/40 (64,000 particles)

struct pressure_run {
    int dim = 2, k = 0;
    std::size_t particles = 0;
    std::uint64_t steps = 0;
    double wall_seconds = 0;
    std::vector<pressure_signal> sensors;  // per impact_pressure_experiments() entry
};

std::string label(const pressure_run& r) { return (r.dim == 3 ? "3D H/" : "H/") + std::to_string(r.k); }

// In 3D the tank and the column are width_3d H wide, the sensors on the far wall's middle line.
std::string tank_scene(int dim, std::size_t particles, const std::string& dam_break_scene) {
    const double L = tank_length * H, top = tank_height * H, W = (dim == 3 ? width_3d : 1.0) * H;
    char text[1024];
    std::snprintf(text, sizeof text, R"({"name": "dam-break-pressure", "solver": "sph", "dim": %d, "particles": %zu,
      "duration": %.17g, "gravity": [0, %g, 0],
      "domain": {"min": [0, 0, 0], "max": [%.17g, %.17g, %.17g]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [%.17g, %.17g, %.17g]}],
      "colliders": [{"type": "box", "inside": true, "center": [%.17g, %.17g, %.17g], "half": [%.17g, %.17g, %.17g]}]})",
                  dim, particles, t_end * std::sqrt(H / g), -g, L, top, W, column_length * H, column_height * H, W,
                  L / 2, top / 2, W / 2, L / 2, top / 2, W / 2);
    // The solver parameters a user gets: the shipped dam break's (or --sph's).
    scene s = parse_scene(text, "dam-break-pressure");
    s.sph = parse_scene(dam_break_scene, "dam-break").sph;
    return scene_to_json(s);
}

pressure_run measure(int dim, int k, const case_context& context) {
    pressure_run r;
    r.dim = dim, r.k = k;
    // The column, 2H x H (x width_3d H in 3D), at spacing H/k.
    const std::size_t particles = dim == 2 ? std::size_t(2 * k * k) : std::size_t(k) * k * k;
    const scene s = parse_scene(tank_scene(dim, particles, context.dam_break_scene), "dam-break-pressure");
    const auto start = std::chrono::steady_clock::now();
    auto sol = make_solver(s, context.threads);
    profiler prof;
    const auto& experiments = impact_pressure_experiments();
    r.sensors.resize(experiments.size());
    const double scale = 1 / (sol->rest_density() * g * H), to_T = std::sqrt(g / H);
    auto sample = [&] {
        const particle_view v = sol->view();
        for (std::size_t e = 0; e < experiments.size(); ++e) {
            const std::array<double, 3> sensor = {tank_length * H, experiments[e].height * H, width_3d * H / 2};
            r.sensors[e].emplace_back(sol->time() * to_T, scale * shepard_pressure(v, sensor, sol->radius()));
        }
    };
    sample();
    while (sol->time() * to_T < t_end) {
        sol->step(prof);
        sample();
    }
    std::string csv = "T";
    for (const auto& e : experiments) csv += "," + e.name;
    csv += "\n";
    for (std::size_t i = 0; i < r.sensors[0].size(); ++i) {
        char row[160];
        std::snprintf(row, sizeof row, "%.6f", r.sensors[0][i].first);
        csv += row;
        for (const auto& sensor : r.sensors) {
            std::snprintf(row, sizeof row, ",%.5f", sensor[i].second);
            csv += row;
        }
        csv += "\n";
    }
    const std::string name = std::string("/pressure-") + (dim == 3 ? "3D-" : "") + "H" + std::to_string(k) + ".csv";
    io::write_file_atomically(context.dir + name, csv);
    r.particles = sol->view().n;
    r.steps = sol->steps();
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

bool is_lowest(const pressure_series& s) { return s.name == "lobovsky-3mm"; }
// The 3D tank is Lobovsky et al.'s; Buchner's was another.
bool measured_in(const pressure_series& s, const pressure_run& r) {
    return r.dim == 2 || s.name.rfind("lobovsky", 0) == 0;
}

// The figures of a signal: arrival, peak (upper sensors) or impulse (lowest). A run whose
// impact comes too late for a window is measured over what it covers; one with no impact
// arrives at its end, with no peak and no impulse.
struct impact_figures {
    double arrival = 0, peak = 0, impulse = 0;
};

impact_figures figures_of(const pressure_signal& s, const pressure_series& sensor) {
    impact_figures f;
    const double end = s.back().first;
    f.arrival = end;
    for (const auto& [T, P] : s)
        if (P >= impact_threshold) {
            f.arrival = arrival_time(s);
            break;
        }
    if (is_lowest(sensor))
        f.impulse = pressure_integral(s, f.arrival, std::min(end, f.arrival + impulse_window));
    else if (std::min(end, f.arrival + peak_window) - f.arrival >= pressure_mean_width)
        f.peak = peak_mean(s, f.arrival, std::min(end, f.arrival + peak_window));
    return f;
}

// The signal in bins of 0.01 in T (their means), for the plot.
pressure_signal binned(const pressure_signal& s) {
    pressure_signal out;
    for (double T = 0.005; T + 0.005 <= s.back().first; T += 0.01) out.emplace_back(T, running_mean(s, T, 0.01));
    return out;
}

std::string pressure_plot(const std::vector<pressure_run>& runs) {
    const auto& experiments = impact_pressure_experiments();
    std::string s = "set termoption noenhanced\nset multiplot layout 2,2 title 'Dam break (WCSPH): pressure on "
                    "the far wall against Buchner (2002) and Lobovsky et al. (2014)'\n";
    const char* colours[] = {"#2471a3", "#229954", "#c0392b", "#7d3c98"};
    int block = 0;
    for (std::size_t e = 0; e < experiments.size(); ++e) {
        char head[256];
        std::snprintf(head, sizeof head,
                      "set title '%s (height %.3gH)'\nset xlabel 'T = t sqrt(g/H)'\nset ylabel 'p / (rho g H)'\n"
                      "set grid\nset key left top\nset xrange [1.5:%g]\n",
                      experiments[e].name.c_str(), experiments[e].height, t_end);
        s += head;
        std::string plot;
        auto add_block = [&](const pressure_signal& points, const std::string& style, const std::string& title) {
            const std::string name = "$d" + std::to_string(block++);
            s += io::gnuplot_data_block(name, points);
            plot += std::string(plot.empty() ? "plot " : ", ") + name + " using 1:2 " + style + " title " +
                    io::gnuplot_quoted(title);
        };
        for (std::size_t r = 0; r < runs.size(); ++r)
            if (measured_in(experiments[e], runs[r]))
                add_block(binned(runs[r].sensors[e]), std::string("with lines lw 1.5 lc rgb '") + colours[r % 4] + "'",
                          std::string(runs[r].dim == 3 ? "frnn 3D" : "frnn") + ", spacing H/" +
                              std::to_string(runs[r].k));
        add_block(experiments[e].points, "with linespoints pt 7 ps 0.6 lw 1 lc rgb '#000000'", "experiment");
        s += plot + "\n";
    }
    return s + "unset multiplot\n";
}

std::string number(const char* format, double value) {
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

}  // namespace

case_output validate_dam_break_pressure(const case_context& context) {
    const std::vector<int> spacings = context.quick ? std::vector<int>{20} : std::vector<int>{50, 100, 200};
    std::vector<pressure_run> runs;  // 2D at each spacing, then (full run) 3D
    for (int k : spacings) {
        if (context.progress)
            std::fprintf(stderr, "dam-break-pressure: 2D, spacing H/%d, %d particles\n", k, 2 * k * k);
        runs.push_back(measure(2, k, context));
    }
    const std::size_t runs_2d = runs.size();
    if (!context.quick) {
        if (context.progress)
            std::fprintf(stderr, "dam-break-pressure: 3D, spacing H/%d, %d particles\n", spacing_3d,
                         spacing_3d * spacing_3d * spacing_3d);
        runs.push_back(measure(3, spacing_3d, context));
    }

    const auto& experiments = impact_pressure_experiments();
    std::vector<impact_figures> measured;
    for (const auto& e : experiments) measured.push_back(figures_of(e.points, e));

    case_output out;
    std::string& md = out.markdown;
    md += "## Dam break (WCSPH): pressure on the far wall\n\n";
    md += "A water column 2H long and H high (H = 0.3 m) at one end of a tank 5.366H long collapses and hits the "
          "far wall (2D; in the full run also 3D in Lobovsky et al.'s tank, 0.5H wide, against their sensors on the "
          "far wall's middle line; WCSPH with the shipped dam break's `sph` section). The pressure at a sensor is "
          "the Shepard average of the fluid particles' pressure within the kernel's support (2h) of its point on the wall, "
          "sampled every step, over rho g H, against T = t sqrt(g/H). Arrival: P first reaches 0.25; peak: the "
          "largest mean over 0.05 in T within 1 after the arrival; impulse: the integral of P over 0.5 after the "
          "arrival; mean error: the mean of |P_sim - P| over T = arrival, arrival + 0.01, ..., 5.5 from the "
          "measured arrival, both averaged over 0.05 in T (P the line through the measured points). Errors of arrival, peak and impulse are relative (frnn/sim/impact_pressure.hpp).\n\n";
    std::string why;
    const bool plotted = io::draw_with_gnuplot(pressure_plot(runs), 1100, 800, context.dir + "/pressure.png", why);
    md += plotted ? "![wall pressure](dam-break-pressure/pressure.png)\n\n" : "(no plot: " + why + ")\n\n";

    md += "| spacing | particles | steps | wall s |\n| --- | ---: | ---: | ---: |\n";
    for (const auto& r : runs)
        md += "| " + label(r) + " | " + std::to_string(r.particles) + " | " + std::to_string(r.steps) +
              " | " + number("%.1f", r.wall_seconds) + " |\n";
    md += "\n| sensor | source | arrival T | peak / impulse | mean error |\n| --- | --- | ---: | ---: | ---: |\n";
    for (std::size_t e = 0; e < experiments.size(); ++e) {
        const auto& sensor = experiments[e];
        const std::string kind = is_lowest(sensor) ? "impulse " : "peak ";
        md += "| " + sensor.name + " | experiment | " + number("%.3f", measured[e].arrival) + " | " + kind +
              number("%.3f", is_lowest(sensor) ? measured[e].impulse : measured[e].peak) + " | |\n";
        for (const auto& r : runs) {
            if (!measured_in(sensor, r)) continue;
            const std::string at = label(r) + ", " + sensor.name + ": ";
            const pressure_signal& sim = r.sensors[e];
            const impact_figures f = figures_of(sim, sensor);
            const double mae = pressure_difference(sim, sensor.points, measured[e].arrival, error_t_hi);
            out.figures.emplace_back(at + "arrival error", std::abs(f.arrival - measured[e].arrival) / measured[e].arrival);
            if (is_lowest(sensor))
                out.figures.emplace_back(at + "impulse error", std::abs(f.impulse - measured[e].impulse) / measured[e].impulse);
            else
                out.figures.emplace_back(at + "peak error", std::abs(f.peak - measured[e].peak) / measured[e].peak);
            out.figures.emplace_back(at + "mean error", mae);
            md += "| " + sensor.name + " | " + label(r) + " | " + number("%.3f", f.arrival) + " | " +
                  kind + number("%.3f", is_lowest(sensor) ? f.impulse : f.peak) + " | " + number("%.3f", mae) + " |\n";
        }
    }
    md += "\n";

    // How the pressure falls with height along the wall after the first impact: water at rest
    // between two sensors gives their height difference over H, water falling freely 0.
    md += "Pressure drop between Lobovsky et al.'s sensors: the mean of P(lower) - P(upper) (each averaged over "
          "0.05 in T) over T = " + number("%.1f", drop_t_lo) + ", ..., " + number("%.1f", error_t_hi) +
          ", after the first impact, in rho g H; water at rest between the sensors gives the static head (their "
          "height difference over H), water falling freely 0:\n\n| sensors | static head | experiment |";
    for (const auto& r : runs) md += " " + label(r).append(" |");
    md += "\n| --- | ---: | ---: |";
    for (std::size_t r = 0; r < runs.size(); ++r) md += " ---: |";
    md += "\n";
    for (std::size_t lower = 1; lower < experiments.size(); ++lower)
        for (std::size_t upper = lower + 1; upper < experiments.size(); ++upper) {
            const std::string pair = experiments[lower].name + " to " + experiments[upper].name;
            const double measured_drop =
                pressure_drop(experiments[lower].points, experiments[upper].points, drop_t_lo, error_t_hi);
            out.figures.emplace_back("experiment: pressure drop " + pair, measured_drop);
            md += "| " + pair + " | " + number("%.3f", experiments[upper].height - experiments[lower].height) + " | " +
                  number("%.3f", measured_drop) + " |";
            for (const auto& r : runs) {
                const double drop = pressure_drop(r.sensors[lower], r.sensors[upper], drop_t_lo, error_t_hi);
                out.figures.emplace_back(label(r) + ": pressure drop " + pair, drop);
                md += " " + number("%.3f", drop).append(" |");
            }
            md += "\n";
        }
    md += "\n";

    if (runs_2d > 1) {  // the 2D spacings
        md += "Self-convergence: D(h1, h2), the mean of |P_h1 - P_h2| (each averaged over 0.05 in T) over T = 2, "
              "2.01, ..., 5.5, in rho g H:\n\n| sensor |";
        for (std::size_t r = 0; r + 1 < runs_2d; ++r)
            md += " D(H/" + std::to_string(runs[r].k) + ", H/" + std::to_string(runs[r + 1].k) + ") |";
        for (std::size_t r = 0; r + 2 < runs_2d; ++r)
            md += " observed order, H/" + std::to_string(runs[r].k) + " to H/" + std::to_string(runs[r + 2].k) + " |";
        md += "\n| --- |";
        for (std::size_t r = 0; r + 3 < 2 * runs_2d; ++r) md += " ---: |";  // (n - 1) D and (n - 2) orders
        md += "\n";
        for (std::size_t e = 0; e < experiments.size(); ++e) {
            md += "| " + experiments[e].name + " |";
            std::vector<double> difference;
            for (std::size_t r = 0; r + 1 < runs_2d; ++r) {
                difference.push_back(
                    pressure_difference(runs[r].sensors[e], runs[r + 1].sensors[e], convergence_t_lo, error_t_hi));
                out.figures.emplace_back("D(H/" + std::to_string(runs[r].k) + ", H/" + std::to_string(runs[r + 1].k) +
                                             "), " + experiments[e].name,
                                         difference.back());
                md += std::string(" ") + number("%.4f", difference.back()) + " |";
            }
            for (std::size_t r = 0; r + 1 < difference.size(); ++r) {
                const double order = std::log2(difference[r] / difference[r + 1]);
                out.figures.emplace_back("observed order, H/" + std::to_string(runs[r].k) + " to H/" +
                                             std::to_string(runs[r + 2].k) + ", " + experiments[e].name,
                                         order);
                md += std::string(" ") + number("%.2f", order) + " |";
            }
            md += "\n";
        }
        md += "\n";
    }
    return out;
}

}  // namespace frnn::sim
