// Builds a grid through the installed package and checks its pair count against the
// brute-force oracle shipped in the same headers.
#include <frnn/frnn.hpp>

#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

int main() {
    // A jittered 3D lattice: deterministic without a random generator.
    std::vector<double> pts;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                for (double v : {i + 0.13 * ((j * 7 + k) % 5), j + 0.11 * ((k * 3 + i) % 7), k * 1.0})
                    pts.push_back(v);
    const double r = 1.5;
    const frnn::grid<double, 3> g(pts, r);
    const auto counts = g.count_neighbors();
    const auto total = std::accumulate(counts.begin(), counts.end(), std::size_t(0));
    const auto oracle = frnn::brute_force_lists<double, 3>(pts, pts, r, true);
    std::printf("frnn consumer (find_package): %zu points, %zu neighbor entries (brute force %zu), %s grid\n",
                g.size(), total, oracle.size(), std::string(frnn::to_string(g.kind())).c_str());
    return total == oracle.size() && total > 0 ? 0 : 1;
}
