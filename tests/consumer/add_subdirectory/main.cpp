// Uses frnn built as a subproject: a periodic 2D float grid, its pair count checked against
// the brute-force oracle.
#include <frnn/grid.hpp>
#include <frnn/brute_force.hpp>

#include <cstdio>
#include <vector>

int main() {
    const std::vector<double> box = {12.0, 9.0};
    std::vector<float> pts;
    for (int i = 0; i < 400; ++i) {
        pts.push_back(float((i * 37 % 120) / 10.0));  // spread over [0, 12)
        pts.push_back(float((i * 53 % 90) / 10.0));   // and [0, 9)
    }
    frnn::grid_options options;
    options.periodic = box;
    const float r = 0.75f;
    const frnn::grid<float, 2> g(pts, r, options);
    frnn::list_options half;
    half.half = true;
    const auto pairs = g.neighbor_lists(half);
    const auto oracle = frnn::brute_force_lists<float, 2>(pts, pts, r, true, box);
    std::printf("frnn consumer (add_subdirectory): %zu points, %zu pairs (brute force %zu entries)\n",
                g.size(), pairs.size(), oracle.size());
    return 2 * pairs.size() == oracle.size() && !pairs.indices.empty() ? 0 : 1;
}
