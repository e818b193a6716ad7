// frnn::mpi::distributor: moves particles, with every per-particle field, to new owner ranks
// (Cabana's Distributor, LAMMPS's exchange). Built once from each local particle's destination;
// then every field goes through migrate() with the same plan. Received particles come grouped
// by source rank in increasing order, each group in the sender's order: the new local order is
// deterministic and the same for every field.
//
// Fields are arrays of any trivially copyable type with `components` values per particle, or
// variable-length data in compressed rows (offsets, values), e.g. the ids of a particle's
// bonded partners.
// Complexity: O(n) per field plus one message per pair of ranks that trade particles.
// Rank safety: construction and every migrate are collective over `comm`, in the same order on
// every rank; a field of the wrong size on any rank throws frnn::error on every rank.
// Thread safety: a const distributor may be shared; one migrate per thread.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "frnn/mpi/collective_error.hpp"
#include "frnn/mpi/communication_plan.hpp"

namespace frnn::mpi {

class distributor {
public:
    distributor() = default;
    /// Collective over `comm`: local particle i goes to rank destinations[i].
    distributor(MPI_Comm comm, std::span<const int> destinations);

    std::size_t local_size() const { return local_size_; }    ///< particles before
    std::size_t import_size() const { return plan_.import_size(); }  ///< particles after
    const communication_plan& plan() const { return plan_; }

    /// The field `values` (local_size() * components) of the particles after the move.
    template <class U>
    std::vector<U> migrate(std::span<const U> values, std::size_t components = 1) const {
        static_assert(std::is_trivially_copyable_v<U>);
        check_size(values.size(), components, "migrate");
        std::vector<U> out(import_size() * components);
        plan_.forward(reinterpret_cast<const std::byte*>(values.data()), sizeof(U) * components,
                      reinterpret_cast<std::byte*>(out.data())).finish();
        return out;
    }
    /// Variable-length data: particle i holds values[offsets[i] .. offsets[i + 1]). Writes the
    /// moved rows into out_offsets (import_size() + 1) and out_values.
    template <class U>
    void migrate(std::span<const std::uint64_t> offsets, std::span<const U> values,
                 std::vector<std::uint64_t>& out_offsets, std::vector<U>& out_values) const {
        static_assert(std::is_trivially_copyable_v<U>);
        const std::vector<std::uint64_t> lengths = row_lengths(offsets, values.size());
        const std::vector<std::uint64_t> moved = migrate(std::span<const std::uint64_t>(lengths));
        out_offsets.assign(moved.size() + 1, 0);
        for (std::size_t i = 0; i < moved.size(); ++i) out_offsets[i + 1] = out_offsets[i] + moved[i];
        out_values.resize(out_offsets.back());
        std::vector<std::size_t> export_bytes, import_bytes(moved.size());
        std::vector<std::byte> packed;
        for (std::uint32_t i : plan_.export_indices()) {
            const std::size_t n = (offsets[i + 1] - offsets[i]) * sizeof(U);
            export_bytes.push_back(n);
            const auto* row = reinterpret_cast<const std::byte*>(values.data() + offsets[i]);
            packed.insert(packed.end(), row, row + n);
        }
        for (std::size_t k = 0; k < moved.size(); ++k) import_bytes[k] = moved[k] * sizeof(U);
        plan_.forward_packed(std::move(packed), export_bytes, import_bytes,
                             reinterpret_cast<std::byte*>(out_values.data())).finish();
    }

private:
    void check_size(std::size_t size, std::size_t components, const char* what) const;
    /// offsets checked (collectively) and turned into row lengths.
    std::vector<std::uint64_t> row_lengths(std::span<const std::uint64_t> offsets, std::size_t values) const;

    communication_plan plan_;
    std::size_t local_size_ = 0;
};

}  // namespace frnn::mpi
