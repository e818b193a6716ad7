// The dam-break reference: the surge front of Martin and Moyce (1952), "Part IV. An
// experimental study of the collapse of liquid columns on a rigid horizontal plane",
// Phil. Trans. R. Soc. Lond. A 244, 312-324: the front Z = x / a against T = t sqrt(2 g / a)
// for a column of width a and height 2a, and a simulation's mean deviation from it.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/sim/run.hpp"

namespace frnn::sim {

const std::vector<std::pair<double, double>>& martin_moyce() {
    static const std::vector<std::pair<double, double>> ref = {{0.832, 1.217}, {1.219, 1.474}, {1.997, 2.292},
                                                               {2.547, 2.995}, {3.345, 4.134}, {4.034, 4.944},
                                                               {4.418, 5.881}, {5.091, 6.980}, {5.685, 7.945}};
    return ref;
}

double front_deviation(const std::vector<std::pair<double, double>>& front, double t_lo, double t_hi) {
    double sum = 0;
    int count = 0;
    for (const auto& [T, Z] : martin_moyce()) {
        if (T < t_lo || T > t_hi) continue;
        if (front.empty() || front.front().first > T || front.back().first < T)
            throw error("front record does not cover T = " + std::to_string(T));
        std::size_t k = 1;
        while (front[k].first < T) ++k;
        const auto& [t0, z0] = front[k - 1];
        const auto& [t1, z1] = front[k];
        const double z = t1 > t0 ? z0 + (z1 - z0) * (T - t0) / (t1 - t0) : z1;
        sum += std::abs(z - Z) / Z;
        ++count;
    }
    if (count == 0) throw error("no reference point of Martin & Moyce in the T range");
    return sum / count;
}

}  // namespace frnn::sim
