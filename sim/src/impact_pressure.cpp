// The wall-pressure reference (frnn/sim/impact_pressure.hpp): the data file's rows, read once
// from the copy compiled in by sim/CMakeLists.txt, the sensor's pressure and the figures.
#include "frnn/sim/impact_pressure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "frnn/error.hpp"
#include "frnn/sim/kernels.hpp"

namespace frnn::sim {

const char* dam_break_pressure_csv();  // generated from sim/data/dam-break-pressure.csv

namespace {

std::vector<pressure_series> parse_series(const std::string& text) {
    const std::vector<std::pair<std::string, double>> sensors = {
        {"buchner-60mm", 0.2}, {"lobovsky-3mm", 0.01}, {"lobovsky-30mm", 0.1}, {"lobovsky-80mm", 0.8 / 3}};
    std::vector<pressure_series> all;
    for (const auto& [name, height] : sensors) all.push_back({name, height, {}});
    std::istringstream in(text);
    std::string line;
    bool header = false;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            header = true;
            continue;
        }
        const auto comma = line.find(',');
        const std::string name = line.substr(0, comma);
        double T = 0, P = 0;
        char c = 0;
        std::istringstream row(comma == std::string::npos ? std::string() : line.substr(comma + 1));
        auto it = std::find_if(all.begin(), all.end(), [&](const pressure_series& s) { return s.name == name; });
        if (it == all.end() || !(row >> T >> c >> P) || c != ',')
            throw error("dam-break-pressure.csv line " + std::to_string(number) + ": not series,T,P: " + line);
        it->points.emplace_back(T, P);
    }
    for (auto& s : all) {
        if (s.points.empty()) throw error("dam-break-pressure.csv: no points of " + s.name);
        std::stable_sort(s.points.begin(), s.points.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    return all;
}

// The index of the first point at T or after (the signal covers T).
std::size_t first_at(const pressure_signal& s, double T) {
    if (s.empty() || s.front().first > T || s.back().first < T)
        throw error("pressure signal does not cover T = " + std::to_string(T));
    return std::size_t(std::lower_bound(s.begin(), s.end(), T, [](const auto& p, double t) { return p.first < t; }) -
                       s.begin());
}

}  // namespace

const std::vector<pressure_series>& impact_pressure_experiments() {
    static const std::vector<pressure_series> series = parse_series(dam_break_pressure_csv());
    return series;
}

double pressure_at(const pressure_signal& s, double T) {
    const std::size_t k = first_at(s, T);
    if (s[k].first == T) return s[k].second;
    const auto& [t0, p0] = s[k - 1];
    return p0 + (s[k].second - p0) * (T - t0) / (s[k].first - t0);
}

double arrival_time(const pressure_signal& s, double threshold) {
    for (std::size_t k = 0; k < s.size(); ++k) {
        if (s[k].second < threshold) continue;
        if (k == 0 || s[k].first == s[k - 1].first) return s[k].first;
        const auto& [t0, p0] = s[k - 1];
        return t0 + (s[k].first - t0) * (threshold - p0) / (s[k].second - p0);
    }
    throw error("pressure signal never reaches " + std::to_string(threshold) + " rho g H");
}

double pressure_integral(const pressure_signal& s, double t_lo, double t_hi) {
    if (!(t_lo <= t_hi)) throw error("pressure_integral: t_lo > t_hi");
    const std::size_t end = first_at(s, t_hi);
    double sum = 0, t = t_lo, p = pressure_at(s, t_lo);
    for (std::size_t k = first_at(s, t_lo); k < end; ++k) {
        if (s[k].first <= t) continue;
        sum += 0.5 * (p + s[k].second) * (s[k].first - t);
        t = s[k].first, p = s[k].second;
    }
    return sum + 0.5 * (p + pressure_at(s, t_hi)) * (t_hi - t);
}

double running_mean(const pressure_signal& s, double T, double width) {
    return pressure_integral(s, T - width / 2, T + width / 2) / width;
}

double peak_mean(const pressure_signal& s, double t_lo, double t_hi, double width) {
    if (!(t_hi - t_lo >= width)) throw error("peak_mean: the window is narrower than the mean's width");
    const int n = int(std::floor((t_hi - t_lo - width) / (width / 20) + 1e-9));
    double best = -INFINITY;
    for (int k = 0; k <= n; ++k) best = std::max(best, running_mean(s, t_lo + width / 2 + k * width / 20, width));
    return best;
}

namespace {
// The mean of f(T) over T = t_lo, t_lo + 0.01, ..., t_hi (the grid's step rounded to divide
// the window).
template <class F>
double time_mean(double t_lo, double t_hi, F f) {
    const int n = std::max(1, int(std::lround((t_hi - t_lo) / 0.01)));
    double sum = 0;
    for (int k = 0; k <= n; ++k) sum += f(t_lo + (t_hi - t_lo) * k / n);
    return sum / (n + 1);
}
}  // namespace

double pressure_difference(const pressure_signal& coarse, const pressure_signal& fine, double t_lo, double t_hi) {
    return time_mean(t_lo, t_hi, [&](double T) { return std::abs(running_mean(coarse, T) - running_mean(fine, T)); });
}

double pressure_drop(const pressure_signal& lower, const pressure_signal& upper, double t_lo, double t_hi) {
    return time_mean(t_lo, t_hi, [&](double T) { return running_mean(lower, T) - running_mean(upper, T); });
}

double shepard_pressure(const particle_view& v, const std::array<double, 3>& point, double support) {
    if (v.dim != 2 && v.dim != 3) throw error("shepard_pressure: the view is neither 2D nor 3D");
    const int d = v.dim;
    const auto weighted_sum = [&](auto w) {
        double weighted = 0, weights = 0;
        for (std::size_t i = 0; i < v.n; ++i) {
            double r2 = 0;
            bool far = false;
            for (int a = 0; a < d; ++a) {
                const double delta = double(v.x[d * i + a]) - point[a];
                far = far || std::abs(delta) >= support;
                r2 += delta * delta;
            }
            if (far) continue;
            const double wi = w(std::sqrt(r2));
            weighted += wi * double(v.p[i]), weights += wi;
        }
        return weights > 0 ? weighted / weights : 0;
    };
    return d == 2 ? weighted_sum(cubic_spline<2>(support)) : weighted_sum(cubic_spline<3>(support));
}

}  // namespace frnn::sim
