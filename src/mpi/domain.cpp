// The distributed search: balance (cut, move), build (ghosts, local grid), neighbor lists.
// The pairs are exactly a single-process grid's. Rows come from frnn's CPU grid over local +
// ghost particles, searched within r at the single-process search scale, where the grid's own
// test is the single-process one. Ghosts that are periodic images hold coordinates shifted by
// a box length, which rounds: their pairs are searched a little wider (a radius per point,
// symmetric rule) and decided again by the single-process test on the coordinates as their
// owners hold them, kept only through the image that is the minimum one. At another search
// scale, or with coordinates the single-process grid would wrap, every pair is decided again.
#include "frnn/mpi/domain.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "frnn/detail/stopwatch.hpp"
#include "frnn/mpi/collective_error.hpp"
#include "frnn/parallel.hpp"
#include "frnn/periodic_wrap.hpp"
#include "frnn/search_scale.hpp"
#include "mpi/check_points.hpp"

namespace frnn::mpi {

namespace {

template <class T, int D>
std::string check_options(T radius, const domain_options& o) {
    if (!(radius > 0) || !std::isfinite(radius)) return "radius " + std::to_string(radius) + " must be finite and > 0";
    if (!(o.skin >= 0) || !std::isfinite(o.skin)) return "skin " + std::to_string(o.skin) + " must be finite and >= 0";
    if (!(o.imbalance >= 0)) return "imbalance threshold " + std::to_string(o.imbalance) + " must be >= 0";
    if (!o.periodic.empty() && o.periodic.size() != std::size_t(D))
        return "periodic box needs " + std::to_string(D) + " lengths, got " + std::to_string(o.periodic.size());
    for (std::size_t a = 0; a < o.periodic.size(); ++a) {
        const double length = o.periodic[a];
        if (length == 0) continue;  // an open axis
        if (!(length > 2 * (double(radius) + o.skin)) || !std::isfinite(length))
            return "periodic box length " + std::to_string(length) + " on axis " + std::to_string(a) +
                   " must be 0 (open) or finite and > 2 (radius + skin) = " + std::to_string(2 * (double(radius) + o.skin));
    }
    return {};
}

using detail::stopwatch;

}  // namespace

template <class T, int D>
domain<T, D>::domain(MPI_Comm comm, T radius, domain_options options)
    : radius_(radius), options_(std::move(options)), candidate_radius_(radius) {
    MPI_Comm_dup(comm, &comm_);
    try {
        std::vector<double> shared{double(radius), options_.skin, options_.imbalance};
        shared.insert(shared.end(), options_.periodic.begin(), options_.periodic.end());
        require_same(comm_, shared, "radius, skin, imbalance threshold and periodic box");
        throw_if_any(comm_, check_options<T, D>(radius, options_));
    } catch (...) {
        MPI_Comm_free(&comm_);
        throw;
    }
    // Shifted images round (x + L) to T: a few units in the last place of L, which the grid's
    // radius must cover for no candidate to be missed (the exact test decides afterwards).
    if (has_periodic_axis()) {
        const double box = *std::max_element(options_.periodic.begin(), options_.periodic.end());
        candidate_radius_ = T(double(radius) * (1 + 1e-6) + 8 * box * std::numeric_limits<T>::epsilon());
    }
}

template <class T, int D>
domain<T, D>::~domain() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Comm_free(&comm_);
}

template <class T, int D>
const distributor& domain<T, D>::balance(std::vector<T>& coords, std::vector<std::uint64_t>& ids,
                                         std::vector<double>* weights, bool rebalance) {
    std::string problem;
    if (coords.size() != ids.size() * D)
        problem = "balance: " + std::to_string(coords.size()) + " coordinates for " + std::to_string(ids.size()) + " ids";
    else
        problem = check_points<T, D>(coords, {}, weights ? std::span<const double>(*weights) : std::span<const double>());
    throw_if_any(comm_, problem);
    // Particles that left the periodic box since the last balance come back into it, wrapped
    // as the single-process grid wraps them. The result lies below T(L), and so below L: when
    // T(L) > L it is the T nearest to L, and no T lies in [L, T(L)).
    for (std::size_t i = 0; i < coords.size() && !options_.periodic.empty(); ++i) {
        const double length = options_.periodic[i % D];
        if (length > 0) coords[i] = wrap_into_box(coords[i], T(length));
    }
    int again = rebalance || !have_cuts_;
    MPI_Allreduce(MPI_IN_PLACE, &again, 1, MPI_INT, MPI_MAX, comm_);
    if (!again) {
        // The weight each rank would own under the present cuts.
        int size = 0;
        MPI_Comm_size(comm_, &size);
        std::vector<double> owned(std::size_t(size), 0.0);
        for (std::size_t i = 0; i < ids.size(); ++i) owned[std::size_t(cuts_.owner(&coords[i * D]))] += weights ? (*weights)[i] : 1.0;
        double mine = 0;
        MPI_Reduce_scatter_block(owned.data(), &mine, 1, MPI_DOUBLE, MPI_SUM, comm_);
        again = imbalance(comm_, mine) > options_.imbalance;
    }
    stopwatch clock;
    stats_ = {};
    if (again) {
        cuts_ = decomposition<T, D>(comm_, coords, double(radius_), options_.periodic,
                                    weights ? std::span<const double>(*weights) : std::span<const double>());
        have_cuts_ = true;
    }
    stats_.decompose_ms = clock.lap_ms();
    moved_ = distributor(comm_, cuts_.owners(coords));
    coords = moved_.migrate(std::span<const T>(coords), D);
    ids = moved_.migrate(std::span<const std::uint64_t>(ids));
    if (weights) *weights = moved_.migrate(std::span<const double>(*weights));
    stats_.migrate_ms = clock.lap_ms();
    stats_.migrate_bytes = moved_.plan().remote_export_size() * (D * sizeof(T) + sizeof(std::uint64_t) + (weights ? sizeof(double) : 0));
    return moved_;
}

template <class T, int D>
void domain<T, D>::build(std::span<const T> coords, std::span<const std::uint64_t> ids) {
    std::string problem;
    if (!have_cuts_) problem = "build before balance: no sub-domains yet";
    else if (coords.size() != ids.size() * D)
        problem = "build: " + std::to_string(coords.size()) + " coordinates for " + std::to_string(ids.size()) + " ids";
    else problem = check_points<T, D>(coords, options_.periodic);
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    for (std::size_t i = 0; problem.empty() && i < ids.size(); ++i)
        if (cuts_.owner(&coords[i * D]) != rank)
            problem = "build: particle " + std::to_string(i) + " (id " + std::to_string(ids[i]) +
                      ") lies outside this rank's sub-domain: balance first";
    throw_if_any(comm_, problem);
    stopwatch clock;
    // The single-process search scale, from every rank's largest coordinate.
    T largest = largest_magnitude<T>(coords, options_.periodic);
    MPI_Allreduce(MPI_IN_PLACE, &largest, 1, sizeof(T) == 4 ? MPI_FLOAT : MPI_DOUBLE, MPI_MAX, comm_);
    scale_ = search_scale<T>(radius_, largest);
    // Ghost reach: the candidates' radius and the skin, with a margin for the rounding of
    // sub-domain faces and of x / cell.
    const double reach = (double(candidate_radius_) + options_.skin) * (1 + 1e-6) + 1e-12 * double(largest);
    halo_ = frnn::mpi::halo<T, D>(comm_, cuts_, coords, reach);
    const std::size_t n = ids.size(), all = n + halo_.ghost_size();
    raw_.assign(all * D, T(0));
    std::copy(coords.begin(), coords.end(), raw_.begin());
    ids_.assign(all, 0);
    std::copy(ids.begin(), ids.end(), ids_.begin());
    pending coordinates = halo_.gather_begin(std::span<T>(raw_), D);
    halo_.gather(std::span<std::uint64_t>(ids_));
    coordinates.finish();
    built_.assign(coords.begin(), coords.end());
    stats_.halo_ms = clock.lap_ms();
    // Each ghost's image (D bytes) with the plan, then its coordinates and id.
    stats_.halo_bytes = halo_.plan().remote_export_size() * (D + D * sizeof(T) + sizeof(std::uint64_t));
    build_grid();
    stats_.grid_ms = clock.lap_ms();
}

template <class T, int D>
bool domain<T, D>::update(std::span<const T> coords) {
    std::string problem;
    if (coords.size() != local_size() * D)
        problem = "update: " + std::to_string(coords.size()) + " coordinates, expected " +
                  std::to_string(local_size()) + " particles x " + std::to_string(D);
    throw_if_any(comm_, problem);
    // Moved no more than skin / 2: every pair within r now was within r + skin at the build.
    const double allowed = options_.skin / 2;
    int moved = 0;
    for (std::size_t i = 0; i < local_size() && !moved; ++i) {
        double d2 = 0;
        for (std::size_t a = 0; a < std::size_t(D); ++a) {
            const double d = double(coords[i * D + a]) - double(built_[i * D + a]);
            d2 += d * d;
        }
        moved = !(d2 <= allowed * allowed);  // NaN too: balance() then reports it
    }
    MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_MAX, comm_);
    if (moved) return false;
    stopwatch clock;
    std::copy(coords.begin(), coords.end(), raw_.begin());
    halo_.gather(std::span<T>(raw_), D);
    stats_ = {};
    stats_.halo_ms = clock.lap_ms();
    stats_.halo_bytes = halo_.plan().remote_export_size() * D * sizeof(T);
    build_grid();
    stats_.grid_ms = clock.lap_ms();
    return true;
}

template <class T, int D>
void domain<T, D>::build_grid() {
    positions_ = raw_;
    halo_.shift_images(positions_);
    grid_options o;
    o.threads = options_.threads;
    const std::size_t n = local_size();
    const std::span<const std::int8_t> images = halo_.ghost_images();
    shifted_.assign(ghost_size(), 0);
    for (std::size_t g = 0; g < shifted_.size(); ++g)
        for (int a = 0; a < D; ++a) shifted_[g] |= images[g * D + std::size_t(a)] != 0;
    in_box_ = true;
    if (has_periodic_axis()) {
        for (std::size_t k = 0; k < raw_.size() && in_box_; ++k) {
            const double length = options_.periodic[k % D];
            in_box_ = !(length > 0) || raw_[k] < T(length);
        }
    }
    if (std::none_of(shifted_.begin(), shifted_.end(), [](char s) { return s != 0; })) {
        grid_.build(positions_, radius_, o);
        return;
    }
    // Only the pairs with a shifted ghost need the widened radius (their coordinates rounded
    // when shifted): the others are searched within r itself, by a radius per point under the
    // symmetric rule.
    radii_.assign(n + ghost_size(), radius_);
    for (std::size_t g = 0; g < shifted_.size(); ++g)
        if (shifted_[g]) radii_[n + g] = candidate_radius_;
    o.rule = radius_rule::symmetric;
    grid_.build(positions_, radii_, o);
}

template <class T, int D>
bool domain<T, D>::has_periodic_axis() const {
    return std::any_of(options_.periodic.begin(), options_.periodic.end(), [](double length) { return length > 0; });
}

template <class T, int D>
bool domain<T, D>::grid_decides() const {
    return grid_.search_scale() == scale_ && in_box_;
}

template <class T, int D>
csr<T> domain<T, D>::neighbor_lists(bool distances) const {
    const std::size_t n = local_size();
    list_options o;
    o.order = row_order::index;
    o.distances = distances;
    // The grid's sweep in cell order over local and ghost particles, rows for the local ones
    // (the first n of positions()).
    o.rows = n;
    csr<T> lists = grid_.neighbor_lists(o);
    const bool exact = grid_decides();
    if (exact && !grid_.has_point_radii()) return lists;  // no shifted ghost
    return decided_by_owners(std::move(lists), distances, exact);
}

template <class T, int D>
csr<T> domain<T, D>::decided_by_owners(csr<T> lists, bool distances, bool only_shifted) const {
    const std::size_t n = local_size();
    const distance_test<T, D> test(radius_, scale_, options_.periodic);
    const std::span<const std::int8_t> images = halo_.ghost_images();
    const std::span<const std::uint32_t> order = grid_.sorted_to_original();
    // Whether candidate j of the point at xi is its neighbor, through the minimum image.
    auto decide = [&](const T* xi, std::uint32_t j, T& d2) {
        const T* xj = &raw_[std::size_t(j) * D];
        if (j < n || !shifted_[j - n]) {
            // Coordinates in the box (which wrapping leaves as they are) whose difference is
            // below half the box on every periodic axis are their own minimum image: the test
            // below without a division.
            T sum = 0;
            bool plain = true;
            for (int a = 0; a < D; ++a) {
                const T d = xj[a] * test.scale - xi[a] * test.scale;
                plain &= !(test.box[a] > 0) || (std::abs(d) * 2 < test.box[a] && xi[a] < test.caller_box[a] &&
                                                xj[a] < test.caller_box[a]);
                sum += d * d;
            }
            if (plain) {
                d2 = sum;
                return d2 <= test.r2;
            }
        }
        bool keep = test.within(xi, xj, d2);
        for (int a = 0; a < D && keep && test.periodic; ++a) {
            if (!(test.box[a] > 0)) continue;  // an open axis: no images
            // The image the single-process test took (as distance_test computes it) must be
            // this candidate's: another image of the same particle would count it twice.
            const T d = xj[a] * test.scale - xi[a] * test.scale;
            const int image = j < n ? 0 : images[(j - n) * D + std::size_t(a)];
            keep = std::nearbyint(d / test.box[a]) == T(-image);
        }
        return keep;
    };
    // Rows are decided in the grid's cell order, where neighboring rows read the same owners'
    // coordinates; a rejected candidate is marked, and rows keep their places.
    constexpr std::uint32_t rejected = std::numeric_limits<std::uint32_t>::max();
    constexpr std::size_t per_chunk = 1024;
    const std::size_t chunks = (order.size() + per_chunk - 1) / per_chunk;
    std::vector<std::size_t> rejections(chunks, 0);
    std::vector<std::uint64_t> kept(n + 1, 0);
    parallel_chunks(chunks, grid_.threads(), [&](std::size_t c, int) {
        const std::size_t end = std::min(order.size(), (c + 1) * per_chunk);
        for (std::size_t s = c * per_chunk; s < end; ++s) {
            const std::uint32_t i = order[s];
            if (i >= n) continue;  // a ghost's row
            const T* xi = &raw_[std::size_t(i) * D];
            std::uint64_t row_kept = 0;
            for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) {
                const std::uint32_t j = lists.indices[k];
                if (only_shifted && (j < n || !shifted_[j - n])) {  // the grid's decision stands
                    ++row_kept;
                    continue;
                }
                T d2;
                const bool keep = decide(xi, j, d2);
                if (!keep) {
                    lists.indices[k] = rejected;
                    ++rejections[c];
                    continue;
                }
                ++row_kept;
                if (distances) lists.distances[k] = test.distance(d2);
            }
            kept[i + 1] = row_kept;
        }
    });
    if (std::accumulate(rejections.begin(), rejections.end(), std::size_t(0)) == 0) return lists;
    // Some candidates were rejected: each chunk of rows closes its gaps in place, then the
    // chunks move down to their new starts, in order (a move never overwrites what a later
    // chunk has yet to move: every start only moves down).
    std::partial_sum(kept.begin(), kept.end(), kept.begin());
    const std::size_t row_chunks = (n + per_chunk - 1) / per_chunk;
    auto chunk_rows = [&](std::size_t c) { return std::pair(c * per_chunk, std::min(n, (c + 1) * per_chunk)); };
    parallel_chunks(row_chunks, grid_.threads(), [&](std::size_t c, int) {
        const auto [b, e] = chunk_rows(c);
        std::uint64_t to = lists.offsets[b];
        for (std::uint64_t k = lists.offsets[b]; k < lists.offsets[e]; ++k) {
            if (lists.indices[k] == rejected) continue;
            lists.indices[to] = lists.indices[k];
            if (distances) lists.distances[to] = lists.distances[k];
            ++to;
        }
    });
    for (std::size_t c = 0; c < row_chunks; ++c) {
        const auto [b, e] = chunk_rows(c);
        const std::uint64_t from = lists.offsets[b], to = kept[b], count = kept[e] - kept[b];
        std::memmove(lists.indices.data() + to, lists.indices.data() + from, count * sizeof(std::uint32_t));
        if (distances) std::memmove(lists.distances.data() + to, lists.distances.data() + from, count * sizeof(T));
    }
    lists.offsets.assign(kept.begin(), kept.end());
    lists.indices.resize(kept[n]);
    if (distances) lists.distances.resize(kept[n]);
    return lists;
}

template <class T, int D>
std::vector<std::array<std::uint64_t, 2>> domain<T, D>::global_pairs() const {
    const csr<T> lists = neighbor_lists();
    std::vector<std::array<std::uint64_t, 2>> pairs;
    pairs.reserve(lists.size());
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint32_t j : lists.row(i)) pairs.push_back({ids_[i], ids_[j]});
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

template class domain<float, 2>;
template class domain<float, 3>;
template class domain<double, 2>;
template class domain<double, 3>;

}  // namespace frnn::mpi
