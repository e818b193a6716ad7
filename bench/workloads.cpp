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

// Jittered lattice of side n in `dim` dimensions, x fastest, spacing 1, jitter +-0.1.
template <class T>
void lattice(std::vector<T>& out, std::size_t n, int dim, draw& rng) {
    const std::size_t nz = dim == 3 ? n : 1;
    for (std::size_t k = 0; k < nz; ++k)
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = 0; i < n; ++i) {
                out.push_back(T(double(i) + rng.uniform(-0.1, 0.1)));
                out.push_back(T(double(j) + rng.uniform(-0.1, 0.1)));
                if (dim == 3) out.push_back(T(double(k) + rng.uniform(-0.1, 0.1)));
            }
}

}  // namespace

const std::vector<workload>& all_workloads() {
    static const std::vector<workload> list{
        {"W1", "lattice", 3, 2.0, {32, 64, 100, 160}, "lattice side"},
        {"W2", "uniform", 3, 2.0, {32768, 262144, 1000000, 4096000}, "points"},
        {"W3", "clustered", 3, 1.0, {1000000}, "points"},
        {"W4", "plane", 2, 2.0, {1000}, "lattice side"},
        {"W5", "outlier", 3, 2.0, {100}, "lattice side"},
    };
    return list;
}

const workload& find_workload(std::string_view id) {
    const std::string want = upper(trim(id));
    for (const auto& w : all_workloads())
        if (w.id == want) return w;
    throw error("unknown workload '" + std::string(id) + "': expected W1, W2, W3, W4, W5 or all");
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

std::size_t point_count(const workload& w, std::size_t size) {
    const double limit = double(std::numeric_limits<std::uint32_t>::max() - 1);
    double count = double(size);
    if (w.size_meaning == "lattice side") count = std::pow(double(size), w.dim);
    if (w.id == "W5") count += 1;
    if (size == 0 || count > limit)
        throw error("workload " + w.id + ": size " + std::to_string(size) +
                    " gives no points or more than 2^32 - 2 (size is the " + w.size_meaning + ")");
    return std::size_t(count);
}

template <class T>
std::vector<T> generate(const workload& w, std::size_t size) {
    const std::size_t n_points = point_count(w, size);
    std::vector<T> out;
    out.reserve(n_points * std::size_t(w.dim));
    draw rng(workload_seed);
    if (w.id == "W1" || w.id == "W4" || w.id == "W5") {
        lattice(out, size, w.dim, rng);
        if (w.id == "W5") out.insert(out.end(), {T(1e7), T(1e7), T(1e7)});
    } else if (w.id == "W2") {
        const double side = std::cbrt(double(size));  // density 1
        for (std::size_t i = 0; i < size * 3; ++i) out.push_back(T(rng.uniform(0.0, side)));
    } else if (w.id == "W3") {
        // 64 Gaussian blobs (sigma 2), centres uniform in [0, 1000)^3, drawn first; point i
        // belongs to blob i mod 64, so the input order is scattered across the blobs.
        constexpr int blobs = 64;
        double centre[blobs][3];
        for (auto& c : centre)
            for (double& x : c) x = rng.uniform(0.0, 1000.0);
        for (std::size_t i = 0; i < size; ++i)
            for (int a = 0; a < 3; ++a) out.push_back(T(centre[i % blobs][a] + 2.0 * rng.normal()));
    } else {
        throw error("workload " + w.id + " has no generator");
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

template std::vector<float> generate<float>(const workload&, std::size_t);
template std::vector<double> generate<double>(const workload&, std::size_t);
template std::vector<float> moved_copy<float>(std::span<const float>);
template std::vector<double> moved_copy<double>(std::span<const double>);

}  // namespace frnn::bench
