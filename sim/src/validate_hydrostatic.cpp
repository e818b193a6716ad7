// The hydrostatic validation case: water at rest in a tank (2D and 3D, depth H = 0.1 m, as
// wide as deep), WCSPH with the shipped dam break's parameters, run for 1 s, the first half a
// settling phase (scene key settle_time: velocities damped). Over the last 20%
// of the run (every 10th step): the least-squares slope of pressure against depth below the
// surface layers and the mean pressure of the bottom layer, against rho0 g and rho0 g H, and
// the largest particle speed against 0.01 sqrt(g H), and (reported) the median particle speed's
// mean over the samples against the same bound. Particle spacing H/20, H/40, H/80 in 2D
// and H/10, H/15, H/20 in 3D; quick: the coarsest of each. Each tank runs twice: from the
// lattice (the goals) and from the lattice with every coordinate moved by up to a tenth of a
// spacing (fluid block key jitter; reported), as a lattice can hold still where disordered
// particles do not.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frnn/sim/profiler.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"
#include "validation_case.hpp"

namespace frnn::sim {

namespace {

constexpr double depth_H = 0.1, duration = 1.0, settle_time = 0.5, settled_from = 0.8, perturbed = 0.1;

struct hydrostatic_result {
    int dim = 2, k = 0;
    double jitter = 0;
    std::size_t particles = 0;
    std::uint64_t steps = 0;
    double slope = 0;   // dp/d(depth) / (rho0 g), mean over the samples
    double bottom = 0;  // bottom-layer pressure / (rho0 g H), mean over the samples
    double speed = 0;   // largest speed / (0.01 sqrt(g H)) over the samples
    double median_speed = 0;  // the median particle speed / (0.01 sqrt(g H)), mean over the samples
};

std::string tank_scene(int dim, std::size_t particles, double jitter, const std::string& dam_break_scene) {
    char text[1024];
    std::snprintf(text, sizeof text, R"({"name": "hydrostatic", "solver": "sph", "dim": %d, "particles": %zu,
      "duration": %g, "gravity": [0, -9.81, 0],
      "domain": {"min": [0, 0, 0], "max": [%g, %g, %g]},
      "fluid": [{"type": "box", "min": [0, 0, 0], "max": [%g, %g, %g], "jitter": %g}],
      "colliders": [{"type": "box", "inside": true, "center": [%g, %g, %g], "half": [%g, %g, %g]}]})",
                  dim, particles, duration, depth_H, 2 * depth_H, depth_H, depth_H, depth_H, depth_H, jitter, depth_H / 2,
                  depth_H, depth_H / 2, depth_H / 2, depth_H, depth_H / 2);
    std::string json = text;
    // The solver parameters a user gets: the shipped dam break's (or --sph's).
    const scene shipped = parse_scene(dam_break_scene, "dam-break");
    scene s = parse_scene(json, "hydrostatic");
    s.sph = shipped.sph;
    s.sph.settle_time = settle_time;
    return scene_to_json(s);
}

hydrostatic_result measure(int dim, int k, double jitter, const case_context& context) {
    hydrostatic_result r;
    r.dim = dim;
    r.k = k;
    r.jitter = jitter;
    const std::size_t target = std::size_t(dim == 2 ? k * k : k * k * k);
    const scene s = parse_scene(tank_scene(dim, target, jitter, context.dam_break_scene), "hydrostatic");
    auto sol = make_solver(s, context.threads);
    profiler prof;
    const double rho0 = sol->rest_density(), g = 9.81;
    const double bound = 0.01 * std::sqrt(g * depth_H);
    int samples = 0;
    std::vector<double> speeds;
    while (sol->time() < duration) {
        sol->step(prof);
        if (sol->time() < settled_from || sol->steps() % 10) continue;
        const particle_view v = sol->view();
        const int up = 1;
        double top = 0;
        for (std::size_t i = 0; i < v.n; ++i) top = std::max(top, double(v.x[dim * i + up]));
        top += sol->spacing() / 2;
        // Below the layers whose kernel support the free surface cuts.
        double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0, bottom = 0, in_bottom = 0, fastest = 0;
        speeds.assign(v.n, 0.0);
        for (std::size_t i = 0; i < v.n; ++i) {
            const double y = v.x[dim * i + up], depth = top - y;
            double speed2 = 0;
            for (int a = 0; a < dim; ++a) speed2 += double(v.v[dim * i + a]) * v.v[dim * i + a];
            speeds[i] = std::sqrt(speed2);
            fastest = std::max(fastest, speeds[i]);
            if (y < sol->spacing()) bottom += v.p[i], in_bottom += 1;
            if (depth < 2 * sol->radius()) continue;
            sx += depth, sy += v.p[i], sxx += depth * depth, sxy += depth * v.p[i], n += 1;
        }
        r.slope += (n * sxy - sx * sy) / (n * sxx - sx * sx) / (rho0 * g);
        // The bottom layer's centres lie half a spacing above the floor.
        r.bottom += bottom / in_bottom / (rho0 * g * (top - sol->spacing() / 2));
        r.speed = std::max(r.speed, fastest / bound);
        // The largest speed is one particle's; the median says how the whole tank moves.
        std::nth_element(speeds.begin(), speeds.begin() + speeds.size() / 2, speeds.end());
        r.median_speed += speeds[speeds.size() / 2] / bound;
        ++samples;
    }
    r.slope /= samples;
    r.bottom /= samples;
    r.median_speed /= samples;
    r.particles = sol->view().n;
    r.steps = sol->steps();
    return r;
}

}  // namespace

case_output validate_hydrostatic(const case_context& context) {
    const std::vector<std::pair<int, std::vector<int>>> plan =
        context.quick ? std::vector<std::pair<int, std::vector<int>>>{{2, {20}}, {3, {10}}}
                      : std::vector<std::pair<int, std::vector<int>>>{{2, {20, 40, 80}}, {3, {10, 15, 20}}};
    std::vector<hydrostatic_result> results;
    for (const auto& [dim, spacings] : plan)
        for (int k : spacings)
            for (const double jitter : {0.0, perturbed}) {
                if (context.progress)
                    std::fprintf(stderr, "hydrostatic: %dD, spacing H/%d, %s\n", dim, k, jitter > 0 ? "perturbed" : "lattice");
                results.push_back(measure(dim, k, jitter, context));
            }

    case_output out;
    std::string& md = out.markdown;
    md += "## Hydrostatic tank (WCSPH)\n\n";
    md += "Water at rest in a tank as wide as it is deep (H = 0.1 m), WCSPH with the shipped dam break's "
          "parameters, 1 s, of which the first 0.5 s settle (velocities damped, scene key settle_time). Over "
          "the last 20% of the run: the slope of pressure against depth (below the "
          "surface layers) over rho0 g, the bottom layer's pressure over rho0 g H, and the largest speed over "
          "0.01 sqrt(g H) (the bound), with the median particle speed's mean over the samples beside it "
          "(reported). Errors are |ratio - 1|. Each tank also starts from the lattice with every coordinate "
          "moved by up to a tenth of a spacing (perturbed; its speeds reported).\n\n";
    md += "| dim | spacing | start | particles | steps | slope / rho0 g | bottom / rho0 g H | max speed / bound | median speed / bound |\n";
    md += "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const auto& r : results) {
        const std::string at = std::to_string(r.dim) + "D H/" + std::to_string(r.k);
        if (r.jitter > 0) {
            out.figures.emplace_back(at + " perturbed: max speed over bound", r.speed);
            out.figures.emplace_back(at + " perturbed: median speed over bound", r.median_speed);
        } else {
            out.figures.emplace_back(at + ": slope error", std::abs(r.slope - 1));
            out.figures.emplace_back(at + ": bottom pressure error", std::abs(r.bottom - 1));
            out.figures.emplace_back(at + ": max speed over bound", r.speed);
            out.figures.emplace_back(at + ": median speed over bound", r.median_speed);
        }
        char row[200];
        std::snprintf(row, sizeof row, "| %dD | H/%d | %s | %zu | %llu | %.4f | %.4f | %.3f | %.4f |\n", r.dim, r.k,
                      r.jitter > 0 ? "perturbed" : "lattice", r.particles, (unsigned long long)r.steps, r.slope,
                      r.bottom, r.speed, r.median_speed);
        md += row;
    }
    md += "\n";
    return out;
}

}  // namespace frnn::sim
