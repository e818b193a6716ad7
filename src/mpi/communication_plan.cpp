// The plan: exports sorted by destination, import counts from one MPI_Alltoall, and the
// non-blocking exchanges built on them.
#include "frnn/mpi/communication_plan.hpp"

#include <algorithm>
#include <climits>
#include <numeric>
#include <string>

#include "frnn/error.hpp"

namespace frnn::mpi {

pending::pending(pending&& other) noexcept
    : requests_(std::move(other.requests_)), buffer_(std::move(other.buffer_)), then_(std::move(other.then_)) {
    other.requests_.clear();
    other.then_ = nullptr;
}

pending& pending::operator=(pending&& other) noexcept {
    if (this != &other) {
        finish();
        requests_ = std::move(other.requests_);
        buffer_ = std::move(other.buffer_);
        then_ = std::move(other.then_);
        other.requests_.clear();
        other.then_ = nullptr;
    }
    return *this;
}

pending::~pending() { finish(); }

void pending::finish() {
    if (!requests_.empty()) MPI_Waitall(int(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
    requests_.clear();
    if (then_) {
        auto then = std::move(then_);
        then_ = nullptr;
        then(buffer_.data());
    }
}

namespace {

int message_size(std::size_t bytes) {
    if (bytes > std::size_t(INT_MAX))
        throw error("MPI message of " + std::to_string(bytes) + " bytes exceeds the 2 GiB limit of one message");
    return int(bytes);
}

/// Posts receives of recv_bytes[k] bytes from recv_ranks[k] into recv + recv_at[k], then sends
/// of send_bytes[k] bytes from send + send_at[k] to send_ranks[k].
void post(MPI_Comm comm, std::vector<MPI_Request>& requests, std::span<const int> recv_ranks,
          std::span<const std::size_t> recv_at, std::span<const std::size_t> recv_bytes, std::byte* recv,
          std::span<const int> send_ranks, std::span<const std::size_t> send_at,
          std::span<const std::size_t> send_bytes, const std::byte* send) {
    for (std::size_t k = 0; k < recv_ranks.size(); ++k) {
        requests.emplace_back();
        MPI_Irecv(recv + recv_at[k], message_size(recv_bytes[k]), MPI_BYTE, recv_ranks[k], message_tag, comm,
                  &requests.back());
    }
    for (std::size_t k = 0; k < send_ranks.size(); ++k) {
        requests.emplace_back();
        MPI_Isend(send + send_at[k], message_size(send_bytes[k]), MPI_BYTE, send_ranks[k], message_tag, comm,
                  &requests.back());
    }
}

/// Byte positions and sizes of element groups given by element offsets.
void byte_ranges(std::span<const std::size_t> offsets, std::size_t bytes, std::vector<std::size_t>& at,
                 std::vector<std::size_t>& size) {
    for (std::size_t k = 0; k + 1 < offsets.size(); ++k) {
        at.push_back(offsets[k] * bytes);
        size.push_back((offsets[k + 1] - offsets[k]) * bytes);
    }
}

/// Byte positions and sizes of element groups whose elements have sizes `element_bytes`.
void group_bytes(std::span<const std::size_t> offsets, std::span<const std::size_t> element_bytes,
                 std::vector<std::size_t>& at, std::vector<std::size_t>& size) {
    std::size_t position = 0;
    for (std::size_t k = 0; k + 1 < offsets.size(); ++k) {
        const std::size_t n = std::accumulate(element_bytes.begin() + std::ptrdiff_t(offsets[k]),
                                              element_bytes.begin() + std::ptrdiff_t(offsets[k + 1]), std::size_t(0));
        at.push_back(position);
        size.push_back(n);
        position += n;
    }
}

}  // namespace

communication_plan::communication_plan(MPI_Comm comm, std::span<const int> destinations,
                                       std::span<const std::uint32_t> sources)
    : comm_(comm) {
    int size = 0;
    MPI_Comm_size(comm, &size);
    if (destinations.size() != sources.size())
        throw error("communication_plan: " + std::to_string(destinations.size()) + " destinations for " +
                    std::to_string(sources.size()) + " sources");
    std::vector<int> send_counts(std::size_t(size), 0), recv_counts(std::size_t(size), 0);
    for (int d : destinations) {
        if (d < 0 || d >= size) throw error("communication_plan: destination rank " + std::to_string(d) + " out of range");
        ++send_counts[std::size_t(d)];
    }
    MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
    // Counting sort by destination: stable, so each destination keeps the caller's order.
    std::vector<std::size_t> start(std::size_t(size) + 1, 0);
    for (int r = 0; r < size; ++r) start[std::size_t(r) + 1] = start[std::size_t(r)] + std::size_t(send_counts[std::size_t(r)]);
    export_index_.resize(sources.size());
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < sources.size(); ++k) export_index_[next[std::size_t(destinations[k])]++] = sources[k];
    export_offsets_.push_back(0);
    import_offsets_.push_back(0);
    for (int r = 0; r < size; ++r) {
        if (send_counts[std::size_t(r)] > 0) {
            export_ranks_.push_back(r);
            export_offsets_.push_back(start[std::size_t(r) + 1]);
        }
        if (recv_counts[std::size_t(r)] > 0) {
            import_ranks_.push_back(r);
            import_offsets_.push_back(import_offsets_.back() + std::size_t(recv_counts[std::size_t(r)]));
        }
    }
}

std::size_t communication_plan::remote_export_size() const {
    if (comm_ == MPI_COMM_NULL) return 0;
    int rank = 0;
    MPI_Comm_rank(comm_, &rank);
    std::size_t n = 0;
    for (std::size_t k = 0; k < export_ranks_.size(); ++k)
        if (export_ranks_[k] != rank) n += export_offsets_[k + 1] - export_offsets_[k];
    return n;
}

pending communication_plan::forward(const std::byte* values, std::size_t bytes, std::byte* imports) const {
    std::vector<std::byte> packed(export_size() * bytes);
    for (std::size_t k = 0; k < export_index_.size(); ++k)
        std::copy_n(values + std::size_t(export_index_[k]) * bytes, bytes, packed.data() + k * bytes);
    const std::vector<std::size_t> export_bytes(export_size(), bytes), import_bytes(import_size(), bytes);
    return forward_packed(std::move(packed), export_bytes, import_bytes, imports);
}

pending communication_plan::reverse(const std::byte* imports, std::size_t bytes,
                                    std::function<void(const std::byte*)> then) const {
    pending p;
    p.buffer_.resize(export_size() * bytes);
    std::vector<std::size_t> send_at, send_bytes, recv_at, recv_bytes;
    byte_ranges(import_offsets_, bytes, send_at, send_bytes);
    byte_ranges(export_offsets_, bytes, recv_at, recv_bytes);
    post(comm_, p.requests_, export_ranks_, recv_at, recv_bytes, p.buffer_.data(), import_ranks_, send_at,
         send_bytes, imports);
    p.then_ = std::move(then);
    return p;
}

pending communication_plan::forward_packed(std::vector<std::byte> packed, std::span<const std::size_t> export_bytes,
                                           std::span<const std::size_t> import_bytes, std::byte* imports) const {
    pending p;
    p.buffer_ = std::move(packed);
    std::vector<std::size_t> send_at, send_bytes, recv_at, recv_bytes;
    group_bytes(export_offsets_, export_bytes, send_at, send_bytes);
    group_bytes(import_offsets_, import_bytes, recv_at, recv_bytes);
    post(comm_, p.requests_, import_ranks_, recv_at, recv_bytes, imports, export_ranks_, send_at, send_bytes,
         p.buffer_.data());
    return p;
}

}  // namespace frnn::mpi
