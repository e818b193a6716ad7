// The README's first example: build a grid, walk one point's neighbors, get CSR lists.
#include <frnn/frnn.hpp>

#include <cstdio>
#include <vector>

int main() {
    std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 5, 5, 5};  // N*3 interleaved coordinates
    frnn::grid<float, 3> grid(xyz, /*radius=*/1.5f);      // the real radius, not its square

    grid.for_each_neighbor(0, [](std::uint32_t j, float d2) { std::printf("0 ~ %u (d^2 %g)\n", j, d2); });

    frnn::list_options opt;
    opt.distances = true;
    opt.order = frnn::row_order::distance;
    frnn::csr<float> lists = grid.neighbor_lists(opt);  // offsets (N+1), indices, distances
    std::printf("%zu entries, point 0 has %zu neighbors\n", lists.size(), lists.row(0).size());
    return lists.size() == 2 ? 0 : 1;
}
