// An oracle that shares no code with the grid nor with frnn/brute_force.hpp: every distance in
// long double, each coordinate wrapped into [0, L) by its own arithmetic, and the minimum image
// chosen as the shortest of the three images d - L, d, d + L of the wrapped difference (not
// d - L*round(d/L), the grid's formula). A wrong minimum image or wrap shared by the grid and
// the brute-force oracle would pass check_all; it cannot pass this.
//
// The grid decides in T, this oracle in long double: they must agree on every pair whose long
// double distance is farther from r than a few roundings of T at the scale of the box and the
// coordinates. Pairs inside that band are counted, not judged.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "frnn/grid.hpp"

namespace frnn::test {

struct independent_counts {
    std::size_t agreed_pairs = 0;      ///< neighbor pairs both found (i != j, each direction)
    std::size_t agreed_non_pairs = 0;  ///< farther than r for both
    std::size_t within_rounding = 0;   ///< within rounding of r: not judged
};

namespace independent {

/// x moved into [0, L) by whole boxes, in long double (L > 0).
inline long double wrapped(long double x, long double box) {
    long double k = std::floor(x / box);
    long double w = x - k * box;
    while (w < 0) w += box;  // floor's quotient may be off by one where x / box rounds
    while (w >= box) w -= box;
    return w;
}

/// The shortest of d - L, d, d + L, for d in (-L, L).
inline long double shortest_image(long double d, long double box) {
    long double best = d;
    for (long double candidate : {d - box, d + box})
        if (std::fabs(candidate) < std::fabs(best)) best = candidate;
    return best;
}

}  // namespace independent

/// Checks the grid's full neighbor lists of `pts` (radius r, the periodic lengths of `box`, 0 for
/// an open axis) against long double distances with the independent minimum image.
template <class T, int D>
independent_counts expect_independent_pairs(const std::vector<T>& pts, T r, const std::vector<double>& box) {
    grid_options opt;
    opt.periodic = box;
    const grid<T, D> g(pts, r, opt);
    list_options lo;
    lo.order = row_order::index;
    const csr<T> lists = g.neighbor_lists(lo);

    const std::size_t n = pts.size() / D;
    std::vector<long double> w(pts.begin(), pts.end());
    long double scale = r;
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < D; ++a) {
            if (box[a] > 0) w[i * D + a] = independent::wrapped(w[i * D + a], box[a]);
            scale = std::max(scale, std::fabs(w[i * D + a]));
        }
    }
    for (int a = 0; a < D; ++a) scale = std::max(scale, (long double)box[a]);
    // The grid wraps and subtracts in T: a few roundings of T at the largest magnitude.
    const long double band = 16 * (long double)std::numeric_limits<T>::epsilon() * scale;

    independent_counts counts;
    std::vector<char> listed(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::fill(listed.begin(), listed.end(), 0);
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) listed[lists.indices[k]] = 1;
        for (std::size_t j = 0; j < n; ++j) {
            if (j == i) continue;
            long double d2 = 0;
            for (int a = 0; a < D; ++a) {
                long double d = w[j * D + a] - w[i * D + a];
                if (box[a] > 0) d = independent::shortest_image(d, box[a]);
                d2 += d * d;
            }
            const long double d = std::sqrt(d2);
            if (std::fabs(d - (long double)r) <= band) {
                ++counts.within_rounding;
                continue;
            }
            const bool near = d < (long double)r;
            EXPECT_EQ(bool(listed[j]), near) << "points " << i << " and " << j << ": long double distance "
                                             << double(d) << " against r = " << double(r) << " (band "
                                             << double(band) << ")";
            if (bool(listed[j]) != near) return counts;  // one report per set is enough
            ++(near ? counts.agreed_pairs : counts.agreed_non_pairs);
        }
    }
    // A set that decides nothing proves nothing: there must be pairs on both sides of r.
    EXPECT_GT(counts.agreed_pairs, 0u) << "no pair within r";
    EXPECT_GT(counts.agreed_non_pairs, 0u) << "no pair beyond r";
    return counts;
}

}  // namespace frnn::test
