// The workloads of bench/README.md (W1..W5, W7, W8), generated in process from std::mt19937_64
// seeded with 42, drawing x, then y, then z of each point in order. O(N) time and memory.
//
// The mapping from the generator's 64-bit words to numbers is fixed here (not left to the
// standard library's distributions, which differ between implementations), so the same size
// gives the same points everywhere:
//   uniform(a, b) = a + (b - a) * (word >> 11) * 2^-53        (one word)
//   normal(0, 1)  = sqrt(-2 ln(1 - u1)) * cos(2 pi u2)         (two words, Box-Muller)
// Thread-safe: the functions share no state.
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace frnn::bench {

struct workload {
    std::string id;                    ///< "W1" .. "W5", "W7", "W8"
    std::string name;                  ///< "lattice", "uniform", ...
    int dim;                           ///< 2 or 3
    double radius;                     ///< search radius of the workload
    std::vector<std::size_t> sizes;    ///< default point counts (rounded as point_count does)
    bool lattice;                      ///< points on a jittered lattice (W1, W4, W5, W8)
    /// Molecular dynamics (W8): an fcc lattice (4 atoms per lattice cell) in a periodic cube,
    /// always in double, with half-list phases and LAMMPS as its baseline.
    bool md = false;
};

/// W1..W5, W7 and W8 in order.
const std::vector<workload>& all_workloads();
/// The workload with this id (case-insensitive); throws frnn::error for an unknown id.
const workload& find_workload(std::string_view id);
/// "all", one id, or a comma list ("W1,W2"); ids returned upper-case, in the order given.
std::vector<std::string> parse_workload_list(std::string_view text);

/// Number of points `w` generates when asked for `n`: n for W2, W3 and W7; for the lattice
/// workloads the lattice count nearest to n (side^3 for W1, side^2 for W4, side^3 + 1 for W5,
/// 4 side^3 for W8; the smaller on a tie). Throws frnn::error when it
/// is 0 or beyond 2^32 - 2 points.
std::size_t point_count(const workload& w, std::size_t n);
/// Side of the lattice of `w` that point_count(w, n) points fill; 0 for W2 and W3.
std::size_t lattice_side(const workload& w, std::size_t n);
/// Number of points of `w`'s lattice of side `side`; throws frnn::error for W2 and W3, and as
/// point_count does.
std::size_t side_count(const workload& w, std::size_t side);

/// The points of `w` asked for `n`: point_count(w, n) * dim interleaved coordinates
/// (x0 y0 [z0] x1 ...).
template <class T>
std::vector<T> generate(const workload& w, std::size_t n);

/// The two point sets of the workloads, also behind `frnn query --generate`:
/// side^dim points at integer positions (x fastest), each coordinate jittered by
/// uniform(-0.1, 0.1) (W1, W4) ...
template <class T>
std::vector<T> jittered_lattice(std::size_t side, int dim, unsigned long long seed);
/// ... and `count` points uniform in the cube (square) of side count^(1/dim), density 1 (W2).
template <class T>
std::vector<T> uniform_cube(std::size_t count, int dim, unsigned long long seed);
/// Points [first, end) of either set alone (end at most its size): the same values, drawn
/// after skipping the generator's draws for the points before (each rank of a distributed
/// query draws only its own slice this way).
template <class T>
std::vector<T> jittered_lattice(std::size_t side, int dim, unsigned long long seed, std::size_t first, std::size_t end);
template <class T>
std::vector<T> uniform_cube(std::size_t count, int dim, unsigned long long seed, std::size_t first, std::size_t end);

/// W7's radii: `count` values uniform in [lo, hi], one per point in point order, from
/// std::mt19937_64 seeded with `seed` (the bench uses 44: the points take 42, the update 43).
template <class T>
std::vector<T> point_radii(std::size_t count, double lo, double hi, unsigned long long seed);

/// W8's lattice constant: 4 atoms per a^3 at LAMMPS's LJ density 0.8442.
double fcc_lattice_constant();
/// The periodic box of an md workload asked for `n` (a cube of this side); 0 for the others.
double periodic_box(const workload& w, std::size_t n);
/// The atoms of W8: the fcc lattice of `side`^3 cells of edge fcc_lattice_constant() (cells in
/// x-fastest order, four atoms each at (0,0,0), (1/2,1/2,0), (1/2,0,1/2), (0,1/2,1/2)), each
/// coordinate moved by uniform(-0.05, 0.05) lattice constants, wrapped into [0, L).
template <class T>
std::vector<T> fcc_lattice(std::size_t side, unsigned long long seed);
/// Seed of the workloads (bench/README.md) and of the "update" motion drawn after them.
inline constexpr unsigned long long workload_seed = 42;
inline constexpr unsigned long long motion_seed = 43;

/// A copy of `coords` with every coordinate moved by uniform(-0.05, 0.05), drawn from
/// std::mt19937_64(motion_seed) in coordinate order: the next step of the "update" phase.
template <class T>
std::vector<T> moved_copy(std::span<const T> coords);

}  // namespace frnn::bench
