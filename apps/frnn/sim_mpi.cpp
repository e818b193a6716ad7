// run_sim_across_ranks (sim_mpi.hpp): frnn::sim's rank_comm over MPI_COMM_WORLD.
#include "sim_mpi.hpp"

#include <mpi.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "command.hpp"
#include "mpi_session.hpp"

namespace frnn::app {
namespace {

class mpi_ranks final : public sim::rank_comm {
public:
    mpi_ranks() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
        // Test hook of the fault tests: FRNN_TEST_KILL_RANK=k and FRNN_TEST_KILL_EXCHANGE=e kill
        // rank k with SIGKILL as it starts its e-th exchange (a WCSPH step makes three), mid-run,
        // while the others wait for it.
        const char* k = std::getenv("FRNN_TEST_KILL_RANK");
        const char* e = std::getenv("FRNN_TEST_KILL_EXCHANGE");
        if (k && e && std::atoi(k) == rank_) kill_at_ = std::strtoull(e, nullptr, 10);
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }

    std::vector<sim::rank_bytes> exchange(const std::vector<sim::rank_bytes>& send) override {
        if (int(send.size()) != size_) throw error("ranks: exchange needs one message per rank");
        if (++exchanges_ == kill_at_) std::raise(SIGKILL);
        const std::size_t ranks = std::size_t(size_);
        std::vector<int> out_count(ranks), out_at(ranks), in_count(ranks), in_at(ranks);
        sim::rank_bytes out;
        for (std::size_t q = 0; q < send.size(); ++q) {
            out_count[q] = count_of(send[q].size());
            out_at[q] = count_of(out.size());
            out.insert(out.end(), send[q].begin(), send[q].end());
        }
        MPI_Alltoall(out_count.data(), 1, MPI_INT, in_count.data(), 1, MPI_INT, MPI_COMM_WORLD);
        std::size_t total = 0;
        for (std::size_t q = 0; q < in_count.size(); ++q) in_at[q] = count_of(total), total += std::size_t(in_count[q]);
        sim::rank_bytes in(total);
        MPI_Alltoallv(out.data(), out_count.data(), out_at.data(), MPI_BYTE, in.data(), in_count.data(), in_at.data(),
                      MPI_BYTE, MPI_COMM_WORLD);
        return split(in, in_count, in_at);
    }

    std::vector<sim::rank_bytes> all_gather(const sim::rank_bytes& mine) override {
        const int n = count_of(mine.size());
        const std::size_t ranks = std::size_t(size_);
        std::vector<int> count(ranks), at(ranks);
        MPI_Allgather(&n, 1, MPI_INT, count.data(), 1, MPI_INT, MPI_COMM_WORLD);
        sim::rank_bytes all(offsets(count, at));
        MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), count.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD);
        return split(all, count, at);
    }

    std::vector<sim::rank_bytes> gather(const sim::rank_bytes& mine) override {
        const int n = count_of(mine.size());
        const std::size_t ranks = std::size_t(size_);
        std::vector<int> count(ranks), at(ranks);
        MPI_Gather(&n, 1, MPI_INT, count.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
        sim::rank_bytes all(rank_ == 0 ? offsets(count, at) : 0);
        MPI_Gatherv(mine.data(), n, MPI_BYTE, all.data(), count.data(), at.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
        if (rank_ != 0) return {};
        return split(all, count, at);
    }

private:
    // MPI counts are int: a larger message would need a derived type (not needed below ~2^31
    // bytes per rank and exchange, about 50 million particles of 40 bytes).
    static int count_of(std::size_t bytes) {
        if (bytes > std::size_t(std::numeric_limits<int>::max()))
            throw error("ranks: a message of " + std::to_string(bytes) + " bytes is beyond MPI's int counts");
        return int(bytes);
    }
    static std::size_t offsets(const std::vector<int>& count, std::vector<int>& at) {
        std::size_t total = 0;
        for (std::size_t q = 0; q < count.size(); ++q) at[q] = count_of(total), total += std::size_t(count[q]);
        count_of(total);
        return total;
    }
    static std::vector<sim::rank_bytes> split(const sim::rank_bytes& all, const std::vector<int>& count,
                                              const std::vector<int>& at) {
        std::vector<sim::rank_bytes> parts(count.size());
        for (std::size_t q = 0; q < count.size(); ++q)
            parts[q].assign(all.begin() + at[q], all.begin() + at[q] + count[q]);
        return parts;
    }
    int rank_ = 0, size_ = 1;
    unsigned long long exchanges_ = 0, kill_at_ = 0;  // kill_at_ 0: never
};

}  // namespace

void run_sim_across_ranks(sim::run_options options, const std::function<void(const sim::run_options&)>& run) {
    int code = 0, rank = 0;
    {
        mpi_session session;
        auto ranks = std::make_shared<mpi_ranks>();
        rank = ranks->rank();
        options.ranks = ranks;
        if (rank != 0) options.progress = false, options.print_table = false;
        try {
            run(options);
        } catch (const sim::ranks_agree_error& e) {
            if (rank == 0) std::fprintf(stderr, "frnn: error: %s\n", e.what());
            code = 1;
        } catch (const std::exception& e) {
            // Raised on this rank alone: the others may wait for it in a collective call.
            std::fprintf(stderr, "frnn: error: rank %d: %s\n", rank, e.what());
            std::fflush(stderr);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        std::fflush(stderr);
    }
    // Rank 0 alone fails the job: a rank failing first could let the launcher end rank 0
    // before its message is out.
    if (code && rank == 0) throw exit_status{code, {}};
}

}  // namespace frnn::app
