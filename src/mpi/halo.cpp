// The halo's plan: for each local particle and each periodic image of it, the ranks whose
// sub-domains lie within reach (a walk of the bisection tree). The images travel once, with
// the plan; coordinates are shifted on arrival.
#include "frnn/mpi/halo.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "frnn/mpi/collective_error.hpp"
#include "mpi/check_points.hpp"

namespace frnn::mpi {

template <class T, int D>
halo<T, D>::halo(MPI_Comm comm, const decomposition<T, D>& domain, std::span<const T> coords, double reach)
    : local_size_(coords.size() / D), box_(domain.periodic().begin(), domain.periodic().end()) {
    throw_if_any(comm, check_points<T, D>(coords, {}));
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    struct ghost {
        int destination;
        std::uint32_t source;
        std::array<std::int8_t, D> image;
    };
    std::vector<ghost> ghosts;
    std::vector<int> near;
    const int images = box_.empty() ? 1 : (D == 2 ? 9 : 27);
    for (std::uint32_t i = 0; i < local_size_; ++i) {
        for (int code = 0; code < images; ++code) {
            // Image `code` in base 3: digit a is the shift on axis a, plus 1.
            std::array<std::int8_t, D> image{};
            double y[D];
            bool useful = true;
            for (int a = 0, rest = code; a < D; ++a, rest /= 3) {
                image[std::size_t(a)] = std::int8_t(box_.empty() ? 0 : rest % 3 - 1);
                const double x = double(coords[i * D + std::size_t(a)]);
                y[a] = x;
                if (image[std::size_t(a)] == 0) continue;
                const double length = box_[std::size_t(a)];
                useful &= length > 0;  // an open axis has no images
                y[a] = x + image[std::size_t(a)] * length;
                // An image further than reach from the box is near no sub-domain.
                useful &= image[std::size_t(a)] > 0 ? y[a] - reach < length : y[a] + reach >= 0;
            }
            if (!useful) continue;
            near.clear();
            domain.ranks_near(y, reach, near);
            const bool shifted = code != (images - 1) / 2;
            for (int q : near)
                if (q != rank || shifted) ghosts.push_back({q, i, image});
        }
    }
    // The plan keeps exports in destination order, stable: sort so that ours match its order.
    std::stable_sort(ghosts.begin(), ghosts.end(), [](const ghost& a, const ghost& b) { return a.destination < b.destination; });
    std::vector<int> destinations;
    std::vector<std::uint32_t> sources;
    std::vector<std::byte> packed;
    for (const ghost& g : ghosts) {
        destinations.push_back(g.destination);
        sources.push_back(g.source);
        for (std::int8_t s : g.image) packed.push_back(std::byte(std::uint8_t(s)));
    }
    plan_ = communication_plan(comm, destinations, sources);
    images_.resize(plan_.import_size() * D);
    const std::vector<std::size_t> export_bytes(plan_.export_size(), D), import_bytes(plan_.import_size(), D);
    plan_.forward_packed(std::move(packed), export_bytes, import_bytes, reinterpret_cast<std::byte*>(images_.data())).finish();
}

template <class T, int D>
void halo<T, D>::check_size(std::size_t size, std::size_t components, const char* what) const {
    std::string problem;
    if (size != (local_size_ + ghost_size()) * components)
        problem = std::string(what) + ": array has " + std::to_string(size) + " values, expected (" +
                  std::to_string(local_size_) + " local + " + std::to_string(ghost_size()) + " ghost) x " +
                  std::to_string(components);
    throw_if_any(plan_.comm(), problem);
}

template <class T, int D>
void halo<T, D>::gather_positions(std::span<T> coords) const {
    gather(coords, D);
    shift_images(coords);
}

template <class T, int D>
void halo<T, D>::shift_images(std::span<T> coords) const {
    // Local work, no messages: a wrong size throws on this rank only.
    if (coords.size() != (local_size_ + ghost_size()) * D)
        throw error("shift_images: array has " + std::to_string(coords.size()) + " values, expected (" +
                    std::to_string(local_size_) + " local + " + std::to_string(ghost_size()) + " ghost) x " +
                    std::to_string(D));
    if (box_.empty()) return;
    for (std::size_t g = 0; g < ghost_size(); ++g)
        for (std::size_t a = 0; a < std::size_t(D); ++a)
            if (const int s = images_[g * D + a]; s != 0) {
                T& x = coords[(local_size_ + g) * D + a];
                x = T(double(x) + s * box_[a]);
            }
}

template class halo<float, 2>;
template class halo<float, 3>;
template class halo<double, 2>;
template class halo<double, 3>;

}  // namespace frnn::mpi
