// LIBRARY.md's example of atoms in a periodic cell: diamond's 2-atom primitive cell, much smaller
// than the cutoff, so that each atom meets many periodic images of both atoms.
#include <frnn/lattice.hpp>

#include <cstdio>
#include <vector>

int main() {
    // Diamond's 2-atom primitive cell (a = 3.567 A): much smaller than a 6 A cutoff.
    const double h = 3.567 / 2;
    frnn::lattice<3> cell{{{{0, h, h}, {h, 0, h}, {h, h, 0}}}, {true, true, true}};
    std::vector<double> atoms{0, 0, 0, h / 2, h / 2, h / 2};
    frnn::lattice_grid<double, 3> g(atoms, cell, 6.0);
    frnn::lattice_list_options want;
    want.distances = true;
    auto lists = g.neighbor_lists(want);  // row i: lists.indices (j), lists.shifts (D per entry: S)

    // Diamond's neighbor shells within 6 A (at 1.545, 2.522, 2.958, ... 5.848 A):
    // 4 + 12 + 12 + 6 + 12 + 24 + 16 + 12 + 24 + 24 + 12 = 158.
    int bonds = 0;
    for (std::uint64_t e = lists.offsets[0]; e < lists.offsets[1]; ++e) bonds += lists.distances[e] < 1.6;
    std::printf("atom 0: %zu neighbors within 6 A through %zu image copies, %d bonds\n",
                std::size_t(lists.offsets[1]), g.image_count(), bonds);
    return lists.offsets[1] == 158 && bonds == 4 ? 0 : 1;
}
