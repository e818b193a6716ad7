// Recursive coordinate bisection on the cell lattice. All ranks cut the nodes of one tree level
// together: one reduction gives each node's extent in cells, then a bisection search over the
// cut's cell index, one reduction of the weights below the candidate cuts per step.
#include "frnn/mpi/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "frnn/mpi/collective_error.hpp"
#include "mpi/check_points.hpp"

namespace frnn::mpi {

namespace {

std::string check_cell(double cell) {
    if (!(cell > 0) || !std::isfinite(cell)) return "cell size " + std::to_string(cell) + " must be finite and > 0";
    return {};
}

/// Sums over all ranks, the same bits on every rank: reduced on rank 0 and broadcast (an
/// Allreduce may add in a different order on different ranks, and the cuts must agree).
void sum_everywhere(MPI_Comm comm, std::vector<double>& values) {
    std::vector<double> total(values.size());
    MPI_Reduce(values.data(), total.data(), int(values.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
    MPI_Bcast(total.data(), int(total.size()), MPI_DOUBLE, 0, comm);
    values = std::move(total);
}

}  // namespace

template <class T, int D>
std::int64_t decomposition<T, D>::cell_index(double x) const {
    const double c = std::floor(x / cell_);
    constexpr double limit = 0x1p62;
    return std::int64_t(std::clamp(c, -limit, limit));
}

template <class T, int D>
decomposition<T, D>::decomposition(MPI_Comm comm, std::span<const T> coords, double cell,
                                   std::span<const double> periodic, std::span<const double> weights)
    : cell_(cell), periodic_(periodic.begin(), periodic.end()) {
    std::vector<double> shared{cell};
    shared.insert(shared.end(), periodic.begin(), periodic.end());
    require_same(comm, shared, "cell size and periodic box");
    std::string problem = check_cell(cell);
    if (problem.empty()) problem = check_points<T, D>(coords, periodic, weights);
    throw_if_any(comm, problem);
    int size = 0;
    MPI_Comm_size(comm, &size);
    const std::size_t n = coords.size() / D;
    unsigned long long local = n, total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
    if (total < static_cast<unsigned long long>(size))
        throw collective_error("more ranks (" + std::to_string(size) + ") than particles (" + std::to_string(total) +
                    "): every rank needs at least one");

    std::vector<std::int64_t> cells(n * D);
    for (std::size_t k = 0; k < cells.size(); ++k) cells[k] = cell_index(double(coords[k]));
    // The tree under construction: each node's ranks [first, last) and faces.
    struct building {
        int first, last;
        std::array<double, D> lower, upper;
    };
    std::vector<building> spans(1);
    spans[0].first = 0;
    spans[0].last = size;
    for (int a = 0; a < D; ++a) {
        const bool wraps = !periodic_.empty() && periodic_[std::size_t(a)] > 0;
        spans[0].lower[std::size_t(a)] = wraps ? 0.0 : -std::numeric_limits<double>::infinity();
        spans[0].upper[std::size_t(a)] = wraps ? periodic_[std::size_t(a)] : std::numeric_limits<double>::infinity();
    }
    nodes_.assign(1, node{});
    std::vector<int> node_of(n, 0);
    std::vector<int> active;  // nodes of several ranks, to be cut
    if (size > 1) active.push_back(0);
    auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
    while (!active.empty()) {
        const std::size_t m = active.size();
        std::vector<int> slot(nodes_.size(), -1);
        for (std::size_t k = 0; k < m; ++k) slot[std::size_t(active[k])] = int(k);
        // Each node's extent in cells: minima and negated maxima in one MIN reduction.
        std::vector<std::int64_t> extent(m * 2 * D, std::numeric_limits<std::int64_t>::max());
        for (std::size_t i = 0; i < n; ++i) {
            const int k = slot[std::size_t(node_of[i])];
            if (k < 0) continue;
            for (int a = 0; a < D; ++a) {
                std::int64_t& lo = extent[std::size_t(k) * 2 * D + std::size_t(a)];
                std::int64_t& hi = extent[std::size_t(k) * 2 * D + D + std::size_t(a)];
                lo = std::min(lo, cells[i * D + std::size_t(a)]);
                hi = std::min(hi, -cells[i * D + std::size_t(a)]);
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, extent.data(), int(extent.size()), MPI_INT64_T, MPI_MIN, comm);
        // Per node: the axis of widest extent and the bisection interval [low, high] of cuts.
        std::vector<int> axis(m, 0);
        std::vector<std::int64_t> low(m, 0), high(m, 0);
        for (std::size_t k = 0; k < m; ++k) {
            const std::int64_t* e = &extent[k * 2 * D];
            if (e[0] == std::numeric_limits<std::int64_t>::max()) continue;  // no particles: cut at 0
            for (int a = 1; a < D; ++a)
                if (-e[D + a] - e[a] > -e[D + axis[k]] - e[axis[k]]) axis[k] = a;
            low[k] = e[axis[k]];
            high[k] = -e[D + axis[k]] + 1;
        }
        // Weights below candidate cuts, for every node at once.
        auto below = [&](const std::vector<std::int64_t>& cut) {
            std::vector<double> w(m, 0.0);
            for (std::size_t i = 0; i < n; ++i) {
                const int k = slot[std::size_t(node_of[i])];
                if (k >= 0 && cells[i * D + std::size_t(axis[std::size_t(k)])] < cut[std::size_t(k)]) w[std::size_t(k)] += weight(i);
            }
            sum_everywhere(comm, w);
            return w;
        };
        const std::vector<double> whole = below(high);
        std::vector<double> target(m);
        for (std::size_t k = 0; k < m; ++k) {
            const building& s = spans[std::size_t(active[k])];
            target[k] = whole[k] * double((s.last - s.first) / 2) / double(s.last - s.first);
        }
        // The smallest cut with at least the target below it.
        for (;;) {
            std::vector<std::int64_t> mid(m);
            bool searching = false;
            for (std::size_t k = 0; k < m; ++k) {
                mid[k] = low[k] + (high[k] - low[k]) / 2;
                searching |= low[k] < high[k];
            }
            if (!searching) break;
            const std::vector<double> w = below(mid);
            for (std::size_t k = 0; k < m; ++k) {
                if (low[k] >= high[k]) continue;
                if (w[k] >= target[k]) high[k] = mid[k];
                else low[k] = mid[k] + 1;
            }
        }
        // That cut or the one before, whichever is nearer the target.
        std::vector<std::int64_t> before(m);
        for (std::size_t k = 0; k < m; ++k) before[k] = low[k] - 1;
        const std::vector<double> at = below(low), at_before = below(before);
        std::vector<int> next;
        for (std::size_t k = 0; k < m; ++k) {
            const std::int64_t first_cell = extent[k * 2 * D + std::size_t(axis[k])];
            std::int64_t cut = low[k];
            if (before[k] >= first_cell && std::abs(at_before[k] - target[k]) <= std::abs(at[k] - target[k])) cut = before[k];
            const int id = active[k];
            const building parent = spans[std::size_t(id)];
            const int middle = parent.first + (parent.last - parent.first) / 2;
            const double face = std::clamp(double(cut) * cell_, parent.lower[std::size_t(axis[k])], parent.upper[std::size_t(axis[k])]);
            building left = parent, right = parent;
            left.last = middle;
            left.upper[std::size_t(axis[k])] = face;
            right.first = middle;
            right.lower[std::size_t(axis[k])] = face;
            nodes_[std::size_t(id)].axis = axis[k];
            nodes_[std::size_t(id)].cut = cut;
            nodes_[std::size_t(id)].left = int(nodes_.size());
            nodes_[std::size_t(id)].right = int(nodes_.size()) + 1;
            for (const building& child : {left, right}) {
                if (child.last - child.first > 1) next.push_back(int(nodes_.size()));
                nodes_.push_back(node{});
                spans.push_back(child);
            }
        }
        for (std::size_t i = 0; i < n; ++i) {
            const node& parent = nodes_[std::size_t(node_of[i])];
            if (parent.left >= 0) node_of[i] = cells[i * D + std::size_t(parent.axis)] < parent.cut ? parent.left : parent.right;
        }
        active = std::move(next);
    }
    lower_.resize(std::size_t(size));
    upper_.resize(std::size_t(size));
    for (std::size_t id = 0; id < nodes_.size(); ++id) {
        if (nodes_[id].left >= 0) continue;
        const building& s = spans[id];
        nodes_[id].rank = s.first;
        lower_[std::size_t(s.first)] = s.lower;
        upper_[std::size_t(s.first)] = s.upper;
    }
}

template <class T, int D>
int decomposition<T, D>::owner(const T* x) const {
    std::size_t id = 0;
    while (nodes_[id].rank < 0) {
        const node& s = nodes_[id];
        id = std::size_t(cell_index(double(x[s.axis])) < s.cut ? s.left : s.right);
    }
    return nodes_[id].rank;
}

template <class T, int D>
std::vector<int> decomposition<T, D>::owners(std::span<const T> coords) const {
    std::vector<int> out(coords.size() / D);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = owner(&coords[i * D]);
    return out;
}

template <class T, int D>
void decomposition<T, D>::ranks_near(const double* x, double reach, std::vector<int>& out) const {
    find_near(0, x, reach, out);
}

template <class T, int D>
void decomposition<T, D>::find_near(int id, const double* x, double reach, std::vector<int>& out) const {
    const node& s = nodes_[std::size_t(id)];
    if (s.rank >= 0) {
        double d2 = 0;
        for (int a = 0; a < D; ++a) {
            const double lo = lower_[std::size_t(s.rank)][std::size_t(a)], hi = upper_[std::size_t(s.rank)][std::size_t(a)];
            const double d = x[a] < lo ? lo - x[a] : x[a] > hi ? x[a] - hi : 0.0;
            d2 += d * d;
        }
        if (d2 <= reach * reach) out.push_back(s.rank);
        return;
    }
    const double face = double(s.cut) * cell_;
    if (x[s.axis] - reach < face) find_near(s.left, x, reach, out);
    if (x[s.axis] + reach >= face) find_near(s.right, x, reach, out);
}

double imbalance(MPI_Comm comm, double local_weight) {
    int size = 0;
    MPI_Comm_size(comm, &size);
    double largest = 0;
    MPI_Allreduce(&local_weight, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
    std::vector<double> total{local_weight};
    sum_everywhere(comm, total);
    const double mean = total[0] / size;
    return mean > 0 ? largest / mean - 1 : 0.0;
}

template class decomposition<float, 2>;
template class decomposition<float, 3>;
template class decomposition<double, 2>;
template class decomposition<double, 3>;

}  // namespace frnn::mpi
