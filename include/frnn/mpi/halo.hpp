// frnn::mpi::halo: ghost copies of other ranks' particles near this rank's sub-domain.
//
// Each rank receives a copy of every particle (of any rank, itself included for periodic
// images) that lies within `reach` (the radius plus a skin) of its sub-domain, with each
// periodic image that does: image coordinates are shifted by whole box lengths, so distances
// to ghosts need no minimum image. The communication plan is built once (construction) and
// reused by every exchange until the caller builds a new halo, e.g. when a particle moved more
// than half the skin.
//
// Per-particle arrays hold the local particles first, then the ghosts in import order
// (grouped by owner rank): size (local_size() + ghost_size()) * components.
//   gather       refreshes the ghosts' values from their owners;
//   scatter_add  sends the ghosts' values back and adds them to their owners' (the ghosts'
//                part is left as it was);
// both blocking or, with *_begin, non-blocking: work on local particles (the interior) while
// the messages travel, then finish() the returned exchange.
// Complexity: construction O(n log ranks) per rank, an exchange O(ghosts) plus one message per
// neighboring rank. Rank safety: construction and exchanges are collective over the
// decomposition's communicator, in the same order on every rank; a wrong array size on any rank
// throws frnn::error on every rank. Thread safety: a const halo may be shared.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include "frnn/mpi/communication_plan.hpp"
#include "frnn/mpi/decomposition.hpp"

namespace frnn::mpi {

template <class T, int D>
class halo {
public:
    halo() = default;
    /// Collective over `comm`: ghosts within `reach` of each rank's sub-domain of `domain`,
    /// for this rank's particles `coords` (n*D values).
    halo(MPI_Comm comm, const decomposition<T, D>& domain, std::span<const T> coords, double reach);

    std::size_t local_size() const { return local_size_; }
    std::size_t ghost_size() const { return plan_.import_size(); }
    const communication_plan& plan() const { return plan_; }
    /// Periodic image of each ghost: D values in {-1, 0, 1}, box lengths added to its owner's
    /// coordinates.
    std::span<const std::int8_t> ghost_images() const { return images_; }

    template <class U>
    void gather(std::span<U> values, std::size_t components = 1) const {
        gather_begin(values, components).finish();
    }
    template <class U>
    pending gather_begin(std::span<U> values, std::size_t components = 1) const {
        static_assert(std::is_trivially_copyable_v<U>);
        check_size(values.size(), components, "gather");
        const std::size_t bytes = sizeof(U) * components;
        auto* data = reinterpret_cast<std::byte*>(values.data());
        return plan_.forward(data, bytes, data + local_size_ * bytes);
    }
    template <class U>
    void scatter_add(std::span<U> values, std::size_t components = 1) const {
        scatter_add_begin(values, components).finish();
    }
    template <class U>
    pending scatter_add_begin(std::span<U> values, std::size_t components = 1) const {
        static_assert(std::is_arithmetic_v<U>, "scatter_add adds: arithmetic types only");
        check_size(values.size(), components, "scatter_add");
        const std::span<const std::uint32_t> targets = plan_.export_indices();
        return plan_.reverse(reinterpret_cast<const std::byte*>(values.data() + local_size_ * components),
                             sizeof(U) * components, [values, components, targets](const std::byte* in) {
                                 // Summed in export order: the same on every run.
                                 for (std::size_t k = 0; k < targets.size(); ++k)
                                     for (std::size_t c = 0; c < components; ++c) {
                                         U v;
                                         std::memcpy(&v, in + (k * components + c) * sizeof(U), sizeof(U));
                                         values[std::size_t(targets[k]) * components + c] += v;
                                     }
                             });
    }
    /// Coordinates (local + ghosts, D values each): gathers the ghosts' from their owners and
    /// shifts them by their periodic images.
    void gather_positions(std::span<T> coords) const;
    /// Shifts the ghosts' part of `coords` by their images (after a plain gather). Local: no
    /// messages, and a wrong size throws on this rank only.
    void shift_images(std::span<T> coords) const;

private:
    void check_size(std::size_t size, std::size_t components, const char* what) const;

    communication_plan plan_;
    std::size_t local_size_ = 0;
    std::vector<std::int8_t> images_;
    std::vector<double> box_;
};

extern template class halo<float, 2>;
extern template class halo<float, 3>;
extern template class halo<double, 2>;
extern template class halo<double, 3>;

}  // namespace frnn::mpi
