// The distributed search: balance (cut, move), build (ghosts, local grid), neighbor lists.
// Candidates come from frnn's CPU grid over local + ghost particles; each is then decided by
// the single-process distance test on the coordinates as their owners hold them (minimum image
// when periodic), and kept only through the image that is the minimum one, so that the pairs
// are exactly a single-process grid's.
#include "frnn/mpi/domain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "frnn/detail/stopwatch.hpp"
#include "frnn/mpi/collective_error.hpp"
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
    if (!options_.periodic.empty()) {
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
    grid_.build(positions_, candidate_radius_, o);
}

template <class T, int D>
csr<T> domain<T, D>::neighbor_lists(bool distances) const {
    const std::size_t n = local_size();
    list_options o;
    o.order = row_order::index;
    const csr<T> candidates = grid_.query(std::span<const T>(positions_).first(n * D), o);
    const distance_test<T, D> test(radius_, scale_, options_.periodic);
    const std::span<const std::int8_t> images = halo_.ghost_images();
    csr<T> out;
    out.offsets.assign(n + 1, 0);
    out.indices.reserve(candidates.size());  // growing it would fault in its pages again and again
    if (distances) out.distances.reserve(candidates.size());
    for (std::size_t i = 0; i < n; ++i) {
        const T* xi = &raw_[i * D];
        for (std::uint32_t j : candidates.row(i)) {
            if (j == i) continue;
            const T* xj = &raw_[std::size_t(j) * D];
            T d2;
            if (!test.within(xi, xj, d2)) continue;
            bool minimum_image = true;
            for (int a = 0; a < D && test.periodic; ++a) {
                if (!(test.box[a] > 0)) continue;  // an open axis: no images
                // The image the single-process test took (as distance_test computes it) must be
                // this candidate's: another image of the same particle would count it twice.
                const T d = xj[a] * test.scale - xi[a] * test.scale;
                const int image = j < n ? 0 : images[(j - n) * D + std::size_t(a)];
                minimum_image &= std::nearbyint(d / test.box[a]) == T(-image);
            }
            if (!minimum_image) continue;
            out.indices.push_back(j);
            if (distances) out.distances.push_back(test.distance(d2));
        }
        out.offsets[i + 1] = out.indices.size();
    }
    return out;
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
