// frnn::lattice_grid against a brute-force oracle over periodic images: every atom pair and
// every shift S whose image can lie within the cutoff, decided by the documented formula
// (frnn/lattice.hpp). The shift ranges come from the oracle's own reciprocal vectors (long
// double, by Cramer's rule), and every listed distance is checked against the long double
// length of the image vector, so a wrong shift or image cannot pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "expect_error.hpp"
#include "frnn/lattice.hpp"

namespace {

using frnn::lattice;
using frnn::lattice_grid;

template <int D>
using key = std::tuple<std::uint32_t, std::uint32_t, std::array<std::int32_t, D>>;

/// Reciprocal vectors of the periodic rows, long double: f_k = x . r_k. Open rows are ignored
/// by giving them a unit normal (any completion works: their shifts are 0).
template <int D>
std::array<std::array<long double, D>, D> reciprocal(const lattice<D>& cell) {
    std::array<std::array<long double, D>, D> m{};
    for (int k = 0; k < D; ++k)
        for (int c = 0; c < D; ++c) m[k][c] = cell.pbc[k] ? cell.vectors[k][c] : 0;
    // Complete open rows by Gram-Schmidt on the unit axes.
    for (int k = 0; k < D; ++k) {
        if (cell.pbc[k]) continue;
        for (int axis = 0; axis < D; ++axis) {
            std::array<long double, D> v{};
            v[axis] = 1;
            for (int q = 0; q < D; ++q) {
                if (q == k) continue;
                long double nq = 0, dq = 0;
                for (int c = 0; c < D; ++c) nq += m[q][c] * m[q][c], dq += v[c] * m[q][c];
                if (nq > 0)
                    for (int c = 0; c < D; ++c) v[c] -= dq / nq * m[q][c];
            }
            long double len = 0;
            for (int c = 0; c < D; ++c) len += v[c] * v[c];
            if (len > 1e-6L) {
                for (int c = 0; c < D; ++c) m[k][c] = v[c] / std::sqrt(len);
                break;
            }
        }
    }
    std::array<std::array<long double, D>, D> r{};
    if constexpr (D == 2) {
        const long double det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        r[0] = {m[1][1] / det, -m[1][0] / det};
        r[1] = {-m[0][1] / det, m[0][0] / det};
    } else {
        auto cross = [](const auto& a, const auto& b) {
            return std::array<long double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                              a[0] * b[1] - a[1] * b[0]};
        };
        const auto bc = cross(m[1], m[2]), ca = cross(m[2], m[0]), ab = cross(m[0], m[1]);
        const long double det = m[0][0] * bc[0] + m[0][1] * bc[1] + m[0][2] * bc[2];
        for (int c = 0; c < 3; ++c) r[0][c] = bc[c] / det, r[1][c] = ca[c] / det, r[2][c] = ab[c] / det;
    }
    return r;
}

template <class T, int D>
struct oracle_entry {
    T distance;
    std::array<T, D> vector;
};

/// Every (i, j, S) within the limit, by the documented formula; limit(i, j) gives the cutoff.
template <class T, int D, class Limit>
std::map<key<D>, oracle_entry<T, D>> oracle(const std::vector<T>& x, const lattice<D>& cell, Limit limit, T reach,
                                            bool strict) {
    const auto r = reciprocal(cell);
    const std::size_t n = x.size() / D;
    std::map<key<D>, oracle_entry<T, D>> out;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            std::array<std::int64_t, D> lo{}, hi{};
            for (int k = 0; k < D; ++k) {
                if (!cell.pbc[k]) continue;
                long double f = 0, len = 0;
                for (int c = 0; c < D; ++c)
                    f += ((long double)x[j * D + c] - x[i * D + c]) * r[k][c], len += r[k][c] * r[k][c];
                const long double m = (long double)reach * std::sqrt(len);
                lo[k] = std::int64_t(std::floor(-m - f)) - 1;
                hi[k] = std::int64_t(std::ceil(m - f)) + 1;
            }
            std::array<std::int64_t, D> s = lo;
            while (true) {
                std::array<std::int32_t, D> shift;
                bool zero = true;
                for (int k = 0; k < D; ++k) shift[k] = std::int32_t(s[k]), zero = zero && s[k] == 0;
                if (!(i == j && zero)) {
                    oracle_entry<T, D> e;
                    T d2 = 0;
                    for (int c = 0; c < D; ++c) {
                        double sc = 0;
                        for (int k = 0; k < D; ++k) sc += double(shift[k]) * (cell.pbc[k] ? cell.vectors[k][c] : 0.0);
                        e.vector[c] = T(x[j * D + c] - x[i * D + c]) + T(sc);
                        d2 += e.vector[c] * e.vector[c];
                    }
                    e.distance = std::sqrt(d2);
                    const T lim = limit(i, j);
                    if (strict ? e.distance < lim : e.distance <= lim)
                        out[{std::uint32_t(i), std::uint32_t(j), shift}] = e;
                }
                int k = 0;
                while (k < D && s[k] == hi[k]) s[k] = lo[k], ++k;
                if (k == D) break;
                ++s[k];
            }
        }
    return out;
}

template <class T, int D>
std::map<key<D>, oracle_entry<T, D>> listed(const frnn::lattice_csr<T, D>& l) {
    std::map<key<D>, oracle_entry<T, D>> out;
    for (std::size_t i = 0; i < l.rows(); ++i)
        for (std::uint64_t e = l.offsets[i]; e < l.offsets[i + 1]; ++e) {
            std::array<std::int32_t, D> s;
            oracle_entry<T, D> v;
            for (int k = 0; k < D; ++k) s[k] = l.shifts[e * D + k], v.vector[k] = l.vectors[e * D + k];
            v.distance = l.distances[e];
            const bool fresh = out.emplace(key<D>{std::uint32_t(i), l.indices[e], s}, v).second;
            EXPECT_TRUE(fresh) << "entry (" << i << ", " << l.indices[e] << ") listed twice with one shift";
        }
    return out;
}

template <int D>
std::string text(const key<D>& k) {
    std::ostringstream s;
    s << "(" << std::get<0>(k) << ", " << std::get<1>(k) << ", S =";
    for (int c = 0; c < D; ++c) s << " " << std::get<2>(k)[c];
    s << ")";
    return s.str();
}

/// Full lists with distances and vectors equal the oracle's, entry for entry and bit for bit;
/// every distance is the long double length of its image vector within rounding.
template <class T, int D>
void check(const std::vector<T>& x, const lattice<D>& cell, T cutoff, const std::vector<T>& radii,
           const std::string& what, bool strict = false) {
    SCOPED_TRACE(what);
    frnn::lattice_options opt;
    opt.strict = strict;
    opt.threads = 1;
    lattice_grid<T, D> g;
    if (radii.empty())
        g.build(x, cell, cutoff, opt);
    else
        g.build(x, cell, radii, opt);
    frnn::lattice_list_options lo;
    lo.distances = lo.vectors = true;
    const auto got = listed(g.neighbor_lists(lo));
    T reach = cutoff;
    if (!radii.empty()) reach = 2 * *std::max_element(radii.begin(), radii.end());
    const auto want = oracle<T, D>(
        x, cell, [&](std::size_t i, std::size_t j) { return radii.empty() ? cutoff : T(radii[i] + radii[j]); },
        reach, strict);
    for (const auto& [k, v] : want) {
        const auto it = got.find(k);
        if (it == got.end()) {
            ADD_FAILURE() << "missing " << text<D>(k) << " at distance " << v.distance;
            continue;
        }
        EXPECT_EQ(it->second.distance, v.distance) << text<D>(k);
        EXPECT_EQ(it->second.vector, v.vector) << text<D>(k);
    }
    for (const auto& [k, v] : got)
        if (!want.count(k)) ADD_FAILURE() << "extra " << text<D>(k) << " at distance " << v.distance;
    // The image vector's true length.
    for (const auto& [k, v] : got) {
        long double d2 = 0, scale = 0;
        const auto [i, j, s] = k;
        for (int c = 0; c < D; ++c) {
            long double sc = 0;
            for (int q = 0; q < D; ++q) sc += (long double)s[q] * (cell.pbc[q] ? cell.vectors[q][c] : 0.0);
            const long double dv = (long double)x[j * D + c] - x[i * D + c] + sc;
            d2 += dv * dv;
            scale = std::max({scale, std::fabs((long double)x[j * D + c]), std::fabs((long double)x[i * D + c]),
                              std::fabs(sc)});
        }
        EXPECT_NEAR(double(std::sqrt(d2)), double(v.distance),
                    8 * double(std::numeric_limits<T>::epsilon()) * double(scale + v.distance))
            << text<D>(k);
    }
}

template <int D>
lattice<D> random_cell(std::mt19937& rng, double length, double shear, std::array<bool, D> pbc, bool left) {
    std::uniform_real_distribution<double> u(-1, 1);
    lattice<D> cell;
    cell.pbc = pbc;
    for (int k = 0; k < D; ++k) {
        cell.vectors[k][k] = length * (1 + 0.2 * u(rng));
        for (int c = 0; c < k; ++c) cell.vectors[k][c] = shear * length * u(rng);
        for (int c = k + 1; c < D; ++c) cell.vectors[k][c] = 0.05 * shear * length * u(rng);
    }
    if (left) cell.vectors[0] = {}, cell.vectors[0][0] = -length;
    return cell;
}

/// Atoms at random fractional coordinates in [-1.5, 2.5) of the cell (outside it too).
template <class T, int D>
std::vector<T> random_atoms(std::mt19937& rng, const lattice<D>& cell, std::size_t n, double length) {
    std::uniform_real_distribution<double> f(-1.5, 2.5);
    std::vector<T> x(n * D);
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < D; ++k) {
            const double t = f(rng);
            for (int c = 0; c < D; ++c) {
                // An open axis may have a zero vector: spread along the unit axis instead.
                const double v = cell.pbc[k] ? cell.vectors[k][c] : (c == k ? length : 0.0);
                x[i * D + c] += T(t * v);
            }
        }
    return x;
}

template <class T, int D>
void random_cells(std::uint32_t seed) {
    std::mt19937 rng(seed);
    const T cutoff = T(1.5);
    int cases = 0;
    for (double ratio : {0.3, 0.7, 1.2, 2.5, 10.0})
        for (double shear : {0.0, 0.3, 0.9, 4.0})
            for (int mask = 0; mask < (1 << D); ++mask) {
                std::array<bool, D> pbc{};
                for (int k = 0; k < D; ++k) pbc[k] = (mask >> k) & 1;
                const bool left = (cases % 3) == 1;
                auto cell = random_cell<D>(rng, ratio * cutoff, shear, pbc, left);
                if (cases % 4 == 3)  // a zero vector on the first open axis
                    for (int k = 0; k < D; ++k)
                        if (!pbc[k]) {
                            cell.vectors[k] = {};
                            break;
                        }
                // Small cells hold many images per atom: fewer atoms keep the oracle quick.
                const std::size_t n = ratio < 1 ? 1 + cases % 9 : ratio < 5 ? 5 + cases % 40 : 60;
                const auto x = random_atoms<T, D>(rng, cell, n, ratio * cutoff);
                check<T, D>(x, cell, cutoff, {},
                            "ratio " + std::to_string(ratio) + ", shear " + std::to_string(shear) + ", pbc mask " +
                                std::to_string(mask) + (left ? ", left-handed" : ""));
                ++cases;
            }
}

TEST(OracleLattice, RandomCellsDouble3D) { random_cells<double, 3>(1); }
TEST(OracleLattice, RandomCellsFloat3D) { random_cells<float, 3>(2); }
TEST(OracleLattice, RandomCellsDouble2D) { random_cells<double, 2>(3); }
TEST(OracleLattice, RandomCellsFloat2D) { random_cells<float, 2>(4); }

// Integer lattices: every distance is a square root of an integer, so many pairs lie exactly at
// an integer cutoff; the formula decides them (<=, or < with strict).
template <class T, int D>
void integer_ties(bool strict) {
    for (int size : {1, 2, 3})
        for (T cutoff : {T(1), T(2), T(3)}) {
            lattice<D> cell;
            for (int k = 0; k < D; ++k) cell.vectors[k][k] = size, cell.pbc[k] = true;
            if (D == 3) cell.vectors[2][0] = 1;  // an integer shear keeps every distance exact
            std::vector<T> x;
            for (int a = 0; a < size; ++a)
                for (int b = 0; b < size; ++b) {
                    x.push_back(T(a));
                    x.push_back(T(b - 3 * size));  // three cells out
                    if (D == 3) x.push_back(T((a + b) % size));
                }
            check<T, D>(x, cell, cutoff, {},
                        "cell " + std::to_string(size) + ", cutoff " + std::to_string(cutoff), strict);
        }
}

TEST(OracleLattice, IntegerTiesDouble3D) { integer_ties<double, 3>(false); }
TEST(OracleLattice, IntegerTiesStrictDouble3D) { integer_ties<double, 3>(true); }
TEST(OracleLattice, IntegerTiesFloat2D) { integer_ties<float, 2>(false); }
TEST(OracleLattice, IntegerTiesStrictFloat3D) { integer_ties<float, 3>(true); }

TEST(OracleLattice, RadiusPerAtomIsPairSum) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> r(0, 1.2);
    for (double ratio : {0.4, 1.5, 4.0}) {
        const auto cell = random_cell<3>(rng, ratio * 1.5, 0.4, {true, true, false}, false);
        const auto x = random_atoms<double, 3>(rng, cell, 30, ratio * 1.5);
        std::vector<double> radii(30);
        for (auto& v : radii) v = r(rng);
        radii[3] = 0;
        check<double, 3>(x, cell, 0, radii, "ratio " + std::to_string(ratio));
        check<double, 3>(x, cell, 0, radii, "strict, ratio " + std::to_string(ratio), true);
    }
}

// Half lists are the full lists' entries with j > i, or j == i and S positive; the self entry
// comes first; sorted rows are sorted; 1 and 2 threads give the same bits.
TEST(OracleLattice, HalfSelfOrderAndThreads) {
    std::mt19937 rng(11);
    const auto cell = random_cell<3>(rng, 2.0, 0.5, {true, true, true}, false);
    const auto x = random_atoms<float, 3>(rng, cell, 300, 2.0);
    frnn::lattice_options one, two;
    one.threads = 1;
    two.threads = 2;
    const lattice_grid<float, 3> g1(x, cell, 2.5f, one), g2(x, cell, 2.5f, two);
    for (auto order : {frnn::row_order::none, frnn::row_order::index, frnn::row_order::distance}) {
        frnn::lattice_list_options lo;
        lo.distances = lo.vectors = true;
        lo.order = order;
        const auto a = g1.neighbor_lists(lo), b = g2.neighbor_lists(lo);
        EXPECT_TRUE(std::equal(a.offsets.begin(), a.offsets.end(), b.offsets.begin(), b.offsets.end()));
        EXPECT_TRUE(std::equal(a.indices.begin(), a.indices.end(), b.indices.begin(), b.indices.end()));
        EXPECT_TRUE(std::equal(a.shifts.begin(), a.shifts.end(), b.shifts.begin(), b.shifts.end()));
        EXPECT_TRUE(std::equal(a.distances.begin(), a.distances.end(), b.distances.begin(), b.distances.end()));
        for (std::size_t i = 0; i + 1 < a.offsets.size(); ++i)
            for (auto e = a.offsets[i] + 1; e < a.offsets[i + 1]; ++e) {
                if (order == frnn::row_order::distance) {
                    ASSERT_LE(a.distances[e - 1], a.distances[e]);
                }
                if (order == frnn::row_order::index) {
                    ASSERT_LE(a.indices[e - 1], a.indices[e]);
                }
            }
    }
    frnn::lattice_list_options full_o, half_o;
    full_o.distances = half_o.distances = half_o.vectors = full_o.vectors = true;
    half_o.half = half_o.self = true;
    const auto full = listed(g1.neighbor_lists(full_o));
    const auto half_lists = g1.neighbor_lists(half_o);
    std::size_t half_entries = 0;
    for (std::size_t i = 0; i < x.size() / 3; ++i) {
        const auto e0 = half_lists.offsets[i];
        ASSERT_EQ(half_lists.indices[e0], i);
        ASSERT_EQ(half_lists.distances[e0], 0.0f);
        for (int k = 0; k < 3; ++k) ASSERT_EQ(half_lists.shifts[e0 * 3 + k], 0);
        for (auto e = e0 + 1; e < half_lists.offsets[i + 1]; ++e) {
            std::array<std::int32_t, 3> s{half_lists.shifts[e * 3], half_lists.shifts[e * 3 + 1], half_lists.shifts[e * 3 + 2]};
            const std::uint32_t j = half_lists.indices[e];
            ASSERT_TRUE(full.count({std::uint32_t(i), j, s}));
            const auto neg = std::array<std::int32_t, 3>{-s[0], -s[1], -s[2]};
            ASSERT_TRUE(full.count({j, std::uint32_t(i), neg})) << "the mirror entry is in the full list";
            ASSERT_TRUE(j > i || (j == i && s > std::array<std::int32_t, 3>{}));
            ++half_entries;
        }
    }
    EXPECT_EQ(2 * half_entries, full.size());
}

// ASE's classic small cells, by the counts that crystallography gives.
TEST(OracleLattice, ClassicCells) {
    auto count_per_atom = [](const std::vector<double>& x, const lattice<3>& cell, double cutoff) {
        const lattice_grid<double, 3> g(x, cell, cutoff);
        const auto l = g.neighbor_lists();
        std::vector<std::size_t> n(l.rows());
        for (std::size_t i = 0; i < l.rows(); ++i) n[i] = l.offsets[i + 1] - l.offsets[i];
        return n;
    };
    // fcc Cu, primitive cell (1 atom, smaller than the cutoff): 12 first and 6 second neighbors.
    const double a = 3.61;
    lattice<3> fcc{{{{0, a / 2, a / 2}, {a / 2, 0, a / 2}, {a / 2, a / 2, 0}}}, {true, true, true}};
    EXPECT_EQ(count_per_atom({0, 0, 0}, fcc, 3.0), std::vector<std::size_t>{12});
    EXPECT_EQ(count_per_atom({0, 0, 0}, fcc, 4.0), std::vector<std::size_t>{18});
    // Diamond, cubic cell of 8 atoms: 4 bonds of a sqrt(3)/4 each.
    const double c = 3.567;
    lattice<3> cubic{{{{c, 0, 0}, {0, c, 0}, {0, 0, c}}}, {true, true, true}};
    std::vector<double> diamond;
    for (auto f : std::vector<std::array<double, 3>>{{0, 0, 0}, {0, .5, .5}, {.5, 0, .5}, {.5, .5, 0},
                                                     {.25, .25, .25}, {.25, .75, .75}, {.75, .25, .75}, {.75, .75, .25}})
        for (double v : f) diamond.push_back(v * c);
    EXPECT_EQ(count_per_atom(diamond, cubic, 1.6), std::vector<std::size_t>(8, 4));
    EXPECT_EQ(count_per_atom(diamond, cubic, 2.6), std::vector<std::size_t>(8, 16));
    // Graphene with vacuum along c (not periodic there, and c zero): 3 bonds of 1.42.
    const double b = 1.42 * std::sqrt(3.0);
    lattice<3> sheet{{{{b, 0, 0}, {b / 2, b * std::sqrt(3.0) / 2, 0}, {0, 0, 0}}}, {true, true, false}};
    EXPECT_EQ(count_per_atom({0, 0, 5, b / 2, b / (2 * std::sqrt(3.0)), 5}, sheet, 1.5), (std::vector<std::size_t>{3, 3}));
    // A water molecule in a box that is not periodic: O has 2 neighbors, each H has O.
    lattice<3> box{{{{10, 0, 0}, {0, 10, 0}, {0, 0, 10}}}, {false, false, false}};
    EXPECT_EQ(count_per_atom({0, 0, 0, 0.757, 0.586, 0, -0.757, 0.586, 0}, box, 1.0), (std::vector<std::size_t>{2, 1, 1}));
}

TEST(OracleLattice, BadInputSaysWhatAndChangesNothing) {
    lattice<3> cell{{{{2, 0, 0}, {0, 2, 0}, {0, 0, 2}}}, {true, true, true}};
    const std::vector<double> x{0.1, 0.2, 0.3, 1, 1, 1};
    lattice_grid<double, 3> g(x, cell, 1.0);
    auto unchanged = [&] {
        EXPECT_EQ(g.size(), 2u);
        EXPECT_EQ(g.neighbor_lists().size(), g.neighbor_lists().size());
    };
    auto flat = cell;
    flat.vectors[2] = {1, 1, 0};
    flat.vectors[1] = {2, 2, 0};  // b parallel to c's projection: with a, b, c coplanar
    frnn::test::expect_error([&] { g.build(x, flat, 1.0); }, {"do not span space"});
    unchanged();
    auto parallel = cell;
    parallel.pbc[2] = false;
    parallel.vectors[1] = {4, 0, 0};
    frnn::test::expect_error([&] { g.build(x, parallel, 1.0); }, {"parallel"});
    auto zero = cell;
    zero.vectors[1] = {};
    frnn::test::expect_error([&] { g.build(x, zero, 1.0); }, {"periodic vector 1 is zero"});
    auto nan = cell;
    nan.vectors[2][1] = std::nan("");
    frnn::test::expect_error([&] { g.build(x, nan, 1.0); }, {"vector 2, component 1 is nan"});
    frnn::test::expect_error([&] { g.build(std::vector<double>{0, 0, 0, 1, std::nan(""), 0}, cell, 1.0); },
                             {"point 1 has coordinate 1"});
    frnn::test::expect_error([&] { g.build(x, cell, 0.0); }, {"cutoff must be finite and > 0"});
    frnn::test::expect_error([&] { g.build(x, cell, std::vector<double>{1.0}); }, {"1 radii for 2 points"});
    frnn::test::expect_error([&] { g.build(x, cell, std::vector<double>{1.0, -1.0}); }, {"radius 1 is -1"});
    frnn::test::expect_error([&] { g.build(std::vector<double>{1, 2}, cell, 1.0); }, {"not whole points"});
    frnn::test::expect_error([&] { g.build(std::vector<double>{1e300, 0, 0}, cell, 1.0); }, {"cells out along lattice vector 0"});
    // Images beyond memory are refused before anything is allocated, with their number.
    frnn::test::expect_error([&] { g.build(x, cell, 5000.0); }, {"periodic images of the 2 atoms"});
    EXPECT_GT((lattice_grid<double, 3>::count_images(x, cell, 5000.0)), std::size_t(2e11));
    unchanged();
}

}  // namespace
