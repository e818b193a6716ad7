// The dam-break reference (frnn/sim/martin_moyce.hpp): the data file's rows, read once from
// the copy compiled in by sim/CMakeLists.txt, and the error of a simulated front.
#include "frnn/sim/martin_moyce.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>

#include "frnn/error.hpp"

namespace frnn::sim {

const char* martin_moyce_csv();  // generated from sim/data/martin-moyce-1952.csv

namespace {

std::vector<front_series> parse_series(const std::string& text) {
    std::vector<front_series> all;
    std::istringstream in(text);
    std::string line;
    bool header = false;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            header = true;
            continue;
        }
        double a = 0, T = 0, Z = 0;
        char c1 = 0, c2 = 0;
        std::istringstream row(line);
        if (!(row >> a >> c1 >> T >> c2 >> Z) || c1 != ',' || c2 != ',')
            throw error("martin-moyce-1952.csv line " + std::to_string(number) + ": not a_in,T,Z: " + line);
        if (all.empty() || all.back().a_inches != a) all.push_back({a, {}});
        auto& points = all.back().points;
        if (!points.empty() && !(T > points.back().first))
            throw error("martin-moyce-1952.csv line " + std::to_string(number) + ": T does not increase");
        points.emplace_back(T, Z);
    }
    return all;
}

}  // namespace

const std::vector<front_series>& martin_moyce() {
    static const std::vector<front_series> series = parse_series(martin_moyce_csv());
    return series;
}

namespace {

// Z at T, linearly interpolated in `front` (sorted by T).
double front_at(const std::vector<std::pair<double, double>>& front, double T) {
    if (front.empty() || front.front().first > T || front.back().first < T)
        throw error("front record does not cover T = " + std::to_string(T));
    std::size_t k = 0;
    while (front[k].first < T) ++k;  // front[k] is the first record at T or after
    if (front[k].first == T) return front[k].second;
    const auto& [t0, z0] = front[k - 1];
    return z0 + (front[k].second - z0) * (T - t0) / (front[k].first - t0);
}

}  // namespace

double front_error(const std::vector<std::pair<double, double>>& front, const front_series& series, double t_lo,
                   double t_hi) {
    double sum = 0;
    const auto errors = signed_front_errors(front, series, t_lo, t_hi);
    for (const auto& [T, e] : errors) sum += std::abs(e);
    return sum / double(errors.size());
}

double front_difference(const std::vector<std::pair<double, double>>& coarse,
                        const std::vector<std::pair<double, double>>& fine, double t_lo, double t_hi) {
    const int n = std::max(1, int(std::lround((t_hi - t_lo) / 0.02)));
    double sum = 0;
    for (int k = 0; k <= n; ++k) {
        const double T = t_lo + (t_hi - t_lo) * k / n, z = front_at(fine, T);
        sum += std::abs(front_at(coarse, T) - z) / z;
    }
    return sum / (n + 1);
}

std::vector<std::pair<double, double>> signed_front_errors(const std::vector<std::pair<double, double>>& front,
                                                           const front_series& series, double t_lo, double t_hi) {
    std::vector<std::pair<double, double>> errors;
    for (const auto& [T, Z] : series.points)
        if (T >= t_lo && T <= t_hi) errors.emplace_back(T, (front_at(front, T) - Z) / Z);
    if (errors.empty()) throw error("no point of Martin & Moyce's series in the T range");
    return errors;
}

std::vector<std::pair<double, double>> richardson_front(const std::vector<std::pair<double, double>>& coarse,
                                                        const std::vector<std::pair<double, double>>& fine, double p,
                                                        double t_lo, double t_hi) {
    if (!(p > 0)) throw error("richardson_front: the order " + std::to_string(p) + " is not positive");
    const int n = std::max(1, int(std::lround((t_hi - t_lo) / 0.02)));
    const double factor = 1 / (std::exp2(p) - 1);
    std::vector<std::pair<double, double>> front;
    for (int k = 0; k <= n; ++k) {
        const double T = t_lo + (t_hi - t_lo) * k / n, z = front_at(fine, T);
        front.emplace_back(T, z + (z - front_at(coarse, T)) * factor);
    }
    return front;
}

}  // namespace frnn::sim
