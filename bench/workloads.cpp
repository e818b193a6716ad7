#include "frnn/bench/workloads.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>

#include "frnn/error.hpp"

namespace frnn::bench {
namespace {

// One fixed mapping from generator words to doubles; see the header.
struct draw {
    std::mt19937_64 engine;
    explicit draw(unsigned long long seed) : engine(seed) {}
    double unit() { return double(engine() >> 11) * 0x1.0p-53; }  // [0, 1)
    double uniform(double a, double b) { return a + (b - a) * unit(); }
    double normal() {
        const double u1 = unit(), u2 = unit();
        return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * std::numbers::pi * u2);
    }
};

std::string upper(std::string_view text) {
    std::string s(text);
    for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

std::string trim(std::string_view text) {
    const auto first = text.find_first_not_of(" \t");
    if (first == std::string_view::npos) return {};
    const auto last = text.find_last_not_of(" \t");
    return std::string(text.substr(first, last - first + 1));
}

constexpr double max_points = double(std::numeric_limits<std::uint32_t>::max() - 1);

// Points of a lattice cell: the four of fcc for md workloads.
double basis(const workload& w) { return w.md ? 4 : 1; }

// Points of w's lattice of side `side`, in double so that a huge side cannot overflow.
double lattice_points(const workload& w, std::size_t side) {
    return basis(w) * std::pow(double(side), w.dim) + (w.id == "W5" ? 1 : 0);  // W5: one far outlier
}

void check_count(const workload& w, double count, const std::string& asked) {
    if (count < 1 || count > max_points)
        throw error("workload " + w.id + ": " + asked + " gives no points or more than 2^32 - 2");
}

}  // namespace

const std::vector<workload>& all_workloads() {
    static const std::vector<workload> list{
        {"W1", "lattice", 3, 2.0, {32768, 262144, 1000000, 4096000}, true},
        {"W2", "uniform", 3, 2.0, {32768, 262144, 1000000, 4096000}, false},
        {"W3", "clustered", 3, 1.0, {1000000}, false},
        {"W4", "plane", 2, 2.0, {1000000}, true},
        {"W5", "outlier", 3, 2.0, {1000000}, true},  // 100^3 + 1 points
        {"W7", "radii", 3, 2.0, {1000000}, false},   // W2's points, radii per point up to 2
        {"W8", "md", 3, 2.8, {32000, 864000}, true, true},  // 4 * 20^3 and 4 * 60^3 atoms
    };
    return list;
}

const workload& find_workload(std::string_view id) {
    const std::string want = upper(trim(id));
    for (const auto& w : all_workloads())
        if (w.id == want) return w;
    throw error("unknown workload '" + std::string(id) + "': expected W1, W2, W3, W4, W5, W7, W8 or all");
}

std::vector<std::string> parse_workload_list(std::string_view text) {
    std::vector<std::string> ids;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = upper(trim(text.substr(start, comma - start)));
        if (item == "ALL") {
            for (const auto& w : all_workloads()) ids.push_back(w.id);
        } else {
            ids.push_back(find_workload(item).id);
        }
        start = comma + 1;
    }
    // A workload named twice is run once, at its first place.
    std::vector<std::string> unique;
    for (auto& id : ids)
        if (std::find(unique.begin(), unique.end(), id) == unique.end()) unique.push_back(id);
    return unique;
}

std::size_t lattice_side(const workload& w, std::size_t n) {
    if (!w.lattice) return 0;
    const double outliers = lattice_points(w, 0);
    // The root's rounding is off by one at most: compare the neighbouring sides too.
    const auto guess = std::size_t(std::llround(std::pow(std::max((double(n) - outliers) / basis(w), 1.0), 1.0 / w.dim)));
    std::size_t best = std::max<std::size_t>(guess, 2) - 1;
    for (std::size_t side = best + 1; side <= guess + 1; ++side)
        if (std::abs(lattice_points(w, side) - double(n)) < std::abs(lattice_points(w, best) - double(n)))
            best = side;
    return best;
}

std::size_t side_count(const workload& w, std::size_t side) {
    if (!w.lattice) throw error("workload " + w.id + " is not a lattice: it has no side (give --n)");
    const double count = side == 0 ? 0 : lattice_points(w, side);
    check_count(w, count, "lattice side " + std::to_string(side));
    return std::size_t(count);
}

std::size_t point_count(const workload& w, std::size_t n) {
    const double count = n == 0 ? 0 : w.lattice ? lattice_points(w, lattice_side(w, n)) : double(n);
    check_count(w, count, "N = " + std::to_string(n));
    return std::size_t(count);
}

template <class T>
std::vector<T> jittered_lattice(std::size_t side, int dim, unsigned long long seed, std::size_t first, std::size_t end) {
    std::vector<T> out;
    out.reserve((end - first) * std::size_t(dim));
    draw rng(seed);
    rng.engine.discard(first * std::size_t(dim));  // every point takes dim draws, x first
    for (std::size_t p = first; p < end; ++p) {
        const std::size_t i = p % side, j = p / side % side, k = p / side / side;
        out.push_back(T(double(i) + rng.uniform(-0.1, 0.1)));
        out.push_back(T(double(j) + rng.uniform(-0.1, 0.1)));
        if (dim == 3) out.push_back(T(double(k) + rng.uniform(-0.1, 0.1)));
    }
    return out;
}

template <class T>
std::vector<T> jittered_lattice(std::size_t side, int dim, unsigned long long seed) {
    return jittered_lattice<T>(side, dim, seed, 0, std::size_t(std::pow(double(side), dim)));
}

template <class T>
std::vector<T> uniform_cube(std::size_t count, int dim, unsigned long long seed, std::size_t first, std::size_t end) {
    draw rng(seed);
    rng.engine.discard(first * std::size_t(dim));
    const double side = dim == 3 ? std::cbrt(double(count)) : std::sqrt(double(count));
    std::vector<T> out((end - first) * std::size_t(dim));
    for (T& x : out) x = T(rng.uniform(0.0, side));
    return out;
}

template <class T>
std::vector<T> uniform_cube(std::size_t count, int dim, unsigned long long seed) {
    return uniform_cube<T>(count, dim, seed, 0, count);
}

template <class T>
std::vector<T> generate(const workload& w, std::size_t n) {
    const std::size_t n_points = point_count(w, n);
    if (w.md) return fcc_lattice<T>(lattice_side(w, n), workload_seed);
    if (w.lattice) {
        std::vector<T> out = jittered_lattice<T>(lattice_side(w, n), w.dim, workload_seed);
        if (w.id == "W5") out.insert(out.end(), {T(1e7), T(1e7), T(1e7)});
        return out;
    }
    if (w.id == "W2" || w.id == "W7") return uniform_cube<T>(n_points, w.dim, workload_seed);
    if (w.id != "W3") throw error("workload " + w.id + " has no generator");
    // 64 Gaussian blobs (sigma 2), centres uniform in [0, 1000)^3, drawn first; point i
    // belongs to blob i mod 64, so the input order is scattered across the blobs.
    constexpr int blobs = 64;
    draw rng(workload_seed);
    double centre[blobs][3];
    for (auto& c : centre)
        for (double& x : c) x = rng.uniform(0.0, 1000.0);
    std::vector<T> out;
    out.reserve(n_points * 3);
    for (std::size_t i = 0; i < n_points; ++i)
        for (int a = 0; a < 3; ++a) out.push_back(T(centre[i % blobs][a] + 2.0 * rng.normal()));
    return out;
}

double fcc_lattice_constant() { return std::cbrt(4.0 / 0.8442); }

double periodic_box(const workload& w, std::size_t n) {
    return w.md ? double(lattice_side(w, n)) * fcc_lattice_constant() : 0.0;
}

template <class T>
std::vector<T> fcc_lattice(std::size_t side, unsigned long long seed) {
    const double a = fcc_lattice_constant(), box = double(side) * a;
    constexpr double offsets[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    draw rng(seed);
    std::vector<T> out;
    out.reserve(4 * side * side * side * 3);
    for (std::size_t k = 0; k < side; ++k)
        for (std::size_t j = 0; j < side; ++j)
            for (std::size_t i = 0; i < side; ++i)
                for (const auto& o : offsets) {
                    const double cell[3] = {double(i), double(j), double(k)};
                    for (int axis = 0; axis < 3; ++axis) {
                        double x = (cell[axis] + o[axis]) * a + rng.uniform(-0.05, 0.05) * a;
                        if (x < 0) x += box;
                        // A value that rounds up to the box length is its image at 0.
                        const T t = T(x);
                        out.push_back(t >= T(box) ? T(0) : t);
                    }
                }
    return out;
}

template <class T>
std::vector<T> moved_copy(std::span<const T> coords) {
    draw rng(motion_seed);
    std::vector<T> out(coords.begin(), coords.end());
    for (T& x : out) x = T(double(x) + rng.uniform(-0.05, 0.05));
    return out;
}

template <class T>
std::vector<T> point_radii(std::size_t count, double lo, double hi, unsigned long long seed) {
    draw rng(seed);
    std::vector<T> out(count);
    for (T& r : out) r = T(rng.uniform(lo, hi));
    return out;
}

template std::vector<float> point_radii<float>(std::size_t, double, double, unsigned long long);
template std::vector<double> point_radii<double>(std::size_t, double, double, unsigned long long);
template std::vector<float> generate<float>(const workload&, std::size_t);
template std::vector<double> generate<double>(const workload&, std::size_t);
template std::vector<float> jittered_lattice<float>(std::size_t, int, unsigned long long);
template std::vector<double> jittered_lattice<double>(std::size_t, int, unsigned long long);
template std::vector<float> uniform_cube<float>(std::size_t, int, unsigned long long);
template std::vector<double> uniform_cube<double>(std::size_t, int, unsigned long long);
template std::vector<float> jittered_lattice<float>(std::size_t, int, unsigned long long, std::size_t, std::size_t);
template std::vector<double> jittered_lattice<double>(std::size_t, int, unsigned long long, std::size_t, std::size_t);
template std::vector<float> uniform_cube<float>(std::size_t, int, unsigned long long, std::size_t, std::size_t);
template std::vector<double> uniform_cube<double>(std::size_t, int, unsigned long long, std::size_t, std::size_t);
template std::vector<float> fcc_lattice<float>(std::size_t, unsigned long long);
template std::vector<double> fcc_lattice<double>(std::size_t, unsigned long long);
template std::vector<float> moved_copy<float>(std::span<const float>);
template std::vector<double> moved_copy<double>(std::span<const double>);

}  // namespace frnn::bench
