// frnn::mpi::communication_plan: who sends which local elements to whom, and where received
// elements go, built once and reused by every exchange (Cabana's CommunicationPlan, LAMMPS's
// swap lists). The halo (ghost copies) and the distributor (moving particles to new owners)
// are both made of one.
//
// Exports are (destination rank, local index) pairs, kept sorted by destination (stable, so
// in the caller's order within one destination). Imports arrive grouped by source rank in
// increasing rank order, each group in the sender's export order: the layout is deterministic.
//
// Exchanges are non-blocking (MPI_Isend/MPI_Irecv with tag message_tag): forward() and
// reverse() post the messages and return a `pending` exchange; the caller may work on other
// data (the interior) before pending::finish() waits for it.
// Complexity: building is O(exports) plus one MPI_Alltoall of the counts (O(ranks) per rank);
// an exchange sends one message per rank pair that shares elements.
// Rank safety: construction is collective over `comm`; every rank must post the same sequence
// of exchanges. Thread safety: a const plan may be shared; one exchange per thread.
#pragma once
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace frnn::mpi {

/// The MPI tag of frnn's point-to-point messages.
inline constexpr int message_tag = 0x4652;

/// An exchange in flight. finish() waits for its messages and then runs its last step (e.g.
/// the additions of a scatter_add); the destructor finishes an unfinished exchange.
class pending {
public:
    pending() = default;
    pending(pending&& other) noexcept;
    pending& operator=(pending&& other) noexcept;
    ~pending();
    void finish();
    bool finished() const { return requests_.empty() && !then_; }

private:
    friend class communication_plan;
    std::vector<MPI_Request> requests_;
    std::vector<std::byte> buffer_;            // packed sends, or received contributions
    std::function<void(const std::byte*)> then_;  // runs on buffer_ once everything arrived
};

class communication_plan {
public:
    communication_plan() = default;
    /// Collective over `comm`: export k sends local element `sources[k]` to rank
    /// `destinations[k]` (a rank may send to itself).
    communication_plan(MPI_Comm comm, std::span<const int> destinations, std::span<const std::uint32_t> sources);

    MPI_Comm comm() const { return comm_; }
    std::size_t export_size() const { return export_index_.size(); }
    std::size_t import_size() const { return import_offsets_.empty() ? 0 : import_offsets_.back(); }
    /// Exports to ranks other than this one (those a network would carry).
    std::size_t remote_export_size() const;
    /// Local indices of the exports, grouped by destination rank.
    std::span<const std::uint32_t> export_indices() const { return export_index_; }
    /// Destination ranks with their first export (export_offsets()[k] .. [k + 1]).
    std::span<const int> export_ranks() const { return export_ranks_; }
    std::span<const std::size_t> export_offsets() const { return export_offsets_; }
    /// Source ranks with their first import.
    std::span<const int> import_ranks() const { return import_ranks_; }
    std::span<const std::size_t> import_offsets() const { return import_offsets_; }

    /// Sends element export_indices()[k] of `values` (`bytes` each) to its destination and
    /// receives the imports into `imports` (import_size() * bytes), which must stay alive and
    /// untouched until the exchange finishes.
    pending forward(const std::byte* values, std::size_t bytes, std::byte* imports) const;
    /// The reverse: sends import k of `imports` back to the rank it came from. Once everything
    /// arrived, `then` receives export_size() * bytes values, export k's at k * bytes.
    pending reverse(const std::byte* imports, std::size_t bytes,
                    std::function<void(const std::byte*)> then) const;
    /// Forward with a different byte count per element (variable-length data):
    /// export_bytes[k] for export k (packed in export order in `packed`), import_bytes[k] for
    /// import k (received, packed, into `imports`).
    pending forward_packed(std::vector<std::byte> packed, std::span<const std::size_t> export_bytes,
                           std::span<const std::size_t> import_bytes, std::byte* imports) const;

private:
    MPI_Comm comm_ = MPI_COMM_NULL;
    std::vector<std::uint32_t> export_index_;
    std::vector<int> export_ranks_, import_ranks_;
    std::vector<std::size_t> export_offsets_, import_offsets_;
};

}  // namespace frnn::mpi
