// frnn_mpi_bench: the distributed rebuild (balance + ghosts + local grid + neighbor lists) of a
// workload of bench/README.md at the number of ranks mpirun started, one line of JSON from rank 0.
// Run it through bench/mpi_scaling.sh, which compares 1, 2 and 4 ranks.
//
// Every rank draws the whole workload (float, seed 42; W8 in its periodic box) and starts with
// a contiguous slice of ids; a first balance + build (not timed) puts the particles on their
// sub-domains. Then each round is the rebuild of one time step: the particles alternate between
// their positions and the "update" motion of bench/README.md (uniform(-0.05, 0.05) per
// coordinate), and the timed part is balance (cuts kept unless the imbalance passes 10%) +
// build + neighbor_lists on every rank, after a barrier; a round's time is the slowest rank's
// sum of its phases. Medians over the rounds after a warm-up round. At 1 rank the plain
// single-process grid (build + lists, same threads, the same periodic box) is timed beside it.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "frnn/bench/workloads.hpp"
#include "frnn/detail/stopwatch.hpp"
#include "frnn/grid.hpp"
#include "frnn/mpi/domain.hpp"

namespace {

using T = float;
constexpr int D = 3;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

/// Per-round figures: this rank's phases, and the totals all ranks agree on.
struct round_figures {
    // The slowest rank's (max over ranks of each; one MPI_Allreduce of these 9 doubles).
    double step_ms = 0, exchange_ms = 0, local_ms = 0;
    double decompose_ms = 0, migrate_ms = 0, halo_ms = 0, grid_ms = 0, lists_ms = 0;
    double bytes = 0, halo_bytes = 0, ghosts = 0, pairs = 0;  // sums over ranks
};

int run(int argc, char** argv) {
    std::string id = "W1";
    std::size_t n = 262144;
    int rounds = 7;
    for (int k = 1; k + 1 < argc; k += 2) {
        if (!std::strcmp(argv[k], "--workload")) id = argv[k + 1];
        else if (!std::strcmp(argv[k], "--n")) n = std::strtoull(argv[k + 1], nullptr, 10);
        else if (!std::strcmp(argv[k], "--rounds")) rounds = std::atoi(argv[k + 1]);
        else {
            std::fprintf(stderr, "usage: frnn_mpi_bench [--workload W1|W2|W8] [--n N] [--rounds K]\n");
            return 2;
        }
    }
    int rank = 0, size = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const frnn::bench::workload& w = frnn::bench::find_workload(id);
    const std::vector<T> still = frnn::bench::generate<T>(w, n);
    const std::vector<T> moved = frnn::bench::moved_copy<T>(still);
    const std::size_t total = still.size() / D;
    const std::size_t begin = total * std::size_t(rank) / std::size_t(size), end = total * std::size_t(rank + 1) / std::size_t(size);
    std::vector<std::uint64_t> ids(end - begin);
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = begin + i;
    auto positions = [&](const std::vector<T>& of) {
        std::vector<T> c(ids.size() * D);
        for (std::size_t i = 0; i < ids.size(); ++i) std::copy_n(&of[ids[i] * D], D, &c[i * D]);
        return c;
    };

    const double box = frnn::bench::periodic_box(w, n);
    frnn::mpi::domain_options options;
    if (box > 0) options.periodic.assign(D, box);
    frnn::mpi::domain<T, D> domain(MPI_COMM_WORLD, T(w.radius), options);
    std::vector<T> coords = positions(still);
    domain.balance(coords, ids);
    double first_bytes = double(domain.stats().migrate_bytes);  // from the initial slices
    domain.build(coords, ids);
    first_bytes += double(domain.stats().halo_bytes);
    MPI_Allreduce(MPI_IN_PLACE, &first_bytes, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);

    std::vector<round_figures> all;
    for (int round = 0; round <= rounds; ++round) {
        coords = positions(round % 2 ? still : moved);
        MPI_Barrier(MPI_COMM_WORLD);
        frnn::detail::stopwatch clock;
        domain.balance(coords, ids);
        const frnn::mpi::domain_stats balanced = domain.stats();
        domain.build(coords, ids);
        const frnn::mpi::domain_stats built = domain.stats();
        clock.lap_ms();
        const frnn::csr<T> lists = domain.neighbor_lists();
        round_figures f;
        f.lists_ms = clock.lap_ms();
        f.decompose_ms = balanced.decompose_ms;
        f.migrate_ms = balanced.migrate_ms;
        f.halo_ms = built.halo_ms;
        f.grid_ms = built.grid_ms;
        f.exchange_ms = f.decompose_ms + f.migrate_ms + f.halo_ms;
        f.local_ms = f.grid_ms + f.lists_ms;
        f.step_ms = f.exchange_ms + f.local_ms;
        double sums[4] = {double(balanced.migrate_bytes + built.halo_bytes), double(built.halo_bytes),
                          double(domain.ghost_size()), double(lists.size())};
        MPI_Allreduce(MPI_IN_PLACE, &f.step_ms, 9, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        MPI_Allreduce(MPI_IN_PLACE, sums, 4, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
        f.bytes = sums[0];
        f.halo_bytes = sums[1];
        f.ghosts = sums[2];
        f.pairs = sums[3];
        if (round > 0) all.push_back(f);  // round 0 warms up
    }

    // The single-process grid on the same particles, at one rank only.
    std::vector<double> serial;
    double serial_pairs = -1;  // -1: not run (more than one rank)
    if (size == 1) {
        for (int round = 0; round <= rounds; ++round) {
            frnn::detail::stopwatch clock;
            frnn::grid_options go;
            go.periodic = options.periodic;
            const frnn::grid<T, D> g(round % 2 ? still : moved, T(w.radius), go);
            frnn::list_options o;
            o.order = frnn::row_order::index;
            const frnn::csr<T> lists = g.neighbor_lists(o);
            if (round > 0) serial.push_back(clock.lap_ms());
            serial_pairs = double(lists.size());
        }
    }
    if (rank != 0) return 0;
    auto med = [&](double round_figures::*field) {
        std::vector<double> v;
        for (const round_figures& f : all) v.push_back(f.*field);
        return median(v);
    };
    const double N = double(total);
    std::printf("{\"workload\": \"%s\", \"n\": %zu, \"ranks\": %d, \"rounds\": %d, \"step_ms\": %.3f, "
                "\"exchange_ms\": %.3f, \"local_ms\": %.3f, \"decompose_ms\": %.3f, \"migrate_ms\": %.3f, "
                "\"halo_ms\": %.3f, \"grid_ms\": %.3f, \"lists_ms\": %.3f, \"bytes_per_particle\": %.3f, "
                "\"halo_bytes_per_particle\": %.3f, \"first_build_bytes_per_particle\": %.3f, "
                "\"ghost_fraction\": %.5f, \"pairs\": %.0f, \"serial_ms\": %.3f, \"serial_pairs\": %.0f}\n",
                w.id.c_str(), total, size, rounds, med(&round_figures::step_ms), med(&round_figures::exchange_ms),
                med(&round_figures::local_ms), med(&round_figures::decompose_ms), med(&round_figures::migrate_ms),
                med(&round_figures::halo_ms), med(&round_figures::grid_ms), med(&round_figures::lists_ms),
                med(&round_figures::bytes) / N, med(&round_figures::halo_bytes) / N, first_bytes / N,
                med(&round_figures::ghosts) / N, all.empty() ? 0.0 : all.back().pairs, median(serial), serial_pairs);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int code = 1;
    try {
        code = run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "frnn_mpi_bench: %s\n", e.what());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
    return code;
}
