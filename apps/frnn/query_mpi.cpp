// The distributed `frnn query`: each rank reads its share of the input, frnn::mpi::domain moves
// the particles to their sub-domains, receives the ghosts and lists the neighbors; the ranks
// write the one output file together, and rank 0 prints the summary with every rank's figures.
// Errors: bad input and failures are collective (every rank stops with the same message and
// exit code 1); an error on one rank alone ends the job with MPI_Abort, so that nothing hangs.
#include "query_mpi.hpp"

#include <mpi.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "frnn/io/read.hpp"
#include "frnn/io/write.hpp"
#include "frnn/mpi/collective_error.hpp"
#include "frnn/mpi/domain.hpp"
#include "command.hpp"
#include "mpi_input.hpp"
#include "mpi_output.hpp"
#include "mpi_session.hpp"

namespace frnn::app {
namespace {

/// What the distributed path cannot do: refused before MPI starts, alike on every rank.
void check_mpi_usage(const query_args& a) {
    auto refuse = [](const char* option, const char* why) {
        throw CLI::ValidationError(option, std::string("is not supported under mpirun: ") + why);
    };
    if (!a.queries.empty()) refuse("--queries", "the distributed search lists the data points' own neighbors");
    if (a.knn) refuse("--knn", "the distributed search lists every neighbor within the radius");
    if (a.self) refuse("--self", "self pairs are not listed by the distributed search");
    if (a.backend != "cpu") refuse("--backend", "each rank searches on its CPU");
    if (a.grid != "auto") refuse("--grid", "each rank chooses its grid kind");
    if (a.cell_size != 0) refuse("--cell-size", "each rank's grid uses cells of the radius");
    if (!a.radius_file.empty()) refuse("--radius", "the distributed search takes one radius, not one per point");
    if (!a.cell.empty()) refuse("--cell", "atoms in a lattice cell are searched in one process");
}

/// The ranks of an MPMD launch (mpirun -np 1 frnn ... : -np 1 frnn ...) could be given other
/// files; the radius and the box the library compares itself.
void require_same_files(MPI_Comm comm, const query_args& a) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    const std::string mine = a.input + '\n' + a.generate + '\n' + std::to_string(a.dim) + '\n' +
                             std::to_string(a.seed) + '\n' + a.output + '\n' + (a.json ? "json" : "text");
    unsigned long long length = mine.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
    std::string reference = rank == 0 ? mine : std::string(length, ' ');
    MPI_Bcast(reference.data(), int(length), MPI_CHAR, 0, comm);
    mpi::throw_if_any(comm, reference == mine ? "" : "INPUT, --output, --generate, --dim, --seed or --json differ from rank 0's");
}

/// Test hook of the fault tests: FRNN_TEST_KILL_RANK=k kills rank k with SIGKILL after the
/// particles moved and before the ghost exchange, while the others wait for it.
void kill_hook(int rank) {
    if (const char* k = std::getenv("FRNN_TEST_KILL_RANK"); k && std::atoi(k) == rank) std::raise(SIGKILL);
}

/// One rank's figures, gathered to rank 0 for the summary (counts as doubles: exact to 2^53).
struct rank_figures {
    double particles = 0, ghosts = 0, pairs = 0;
    double decompose_ms = 0, migrate_ms = 0, halo_ms = 0, grid_ms = 0, lists_ms = 0;
    double migrate_bytes = 0, halo_bytes = 0;
};
constexpr int figure_count = sizeof(rank_figures) / sizeof(double);

struct mpi_report {
    int ranks = 1, dimension = 3;
    std::string precision;
    std::uint64_t points = 0, pairs = 0;
    double read_ms = 0, search_ms = 0, write_ms = 0;
    std::vector<rank_figures> per_rank;
};

/// This rank's rows in global ids, sorted by neighbor id, keeping what `filter` keeps.
template <class T, int D>
global_rows<T> rows_of(const mpi::domain<T, D>& d, const csr<T>& lists, io::pair_filter filter, bool distances) {
    global_rows<T> out;
    const std::span<const std::uint64_t> ids = d.ids();
    std::vector<std::pair<std::uint64_t, T>> row;
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        row.clear();
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k)
            if (filter == io::pair_filter::all || ids[lists.indices[k]] >= ids[i])
                row.emplace_back(ids[lists.indices[k]], lists.distances[k]);
        std::sort(row.begin(), row.end());
        out.ids.push_back(ids[i]);
        out.lengths.push_back(row.size());
        for (const auto& [j, r] : row) {
            out.neighbors.push_back(std::uint32_t(j));
            if (distances) out.distances.push_back(r);
        }
    }
    return out;
}

/// This rank's pairs with i < j in global ids: those its rows hold with a greater neighbor id.
template <class T, int D>
std::uint64_t upper_pairs(const mpi::domain<T, D>& d, const csr<T>& lists) {
    const std::span<const std::uint64_t> ids = d.ids();
    std::uint64_t n = 0;
    for (std::size_t i = 0; i < lists.rows(); ++i)
        for (std::uint64_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) n += ids[lists.indices[k]] > ids[i];
    return n;
}

template <class T, int D>
void search(MPI_Comm comm, const query_args& a, const input_slice& in, mpi_report& report) {
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    stopwatch clock;
    const auto& xyz = std::get<std::vector<T>>(in.points.coords);
    std::vector<T> coords(xyz.begin(), xyz.end());
    std::vector<std::uint64_t> ids(coords.size() / D);
    std::iota(ids.begin(), ids.end(), in.first);
    mpi::domain_options options;
    options.periodic = a.periodic.empty() ? std::vector<double>{} : parse_periodic(a.periodic);
    options.threads = a.threads;
    mpi::domain<T, D> d(comm, T(a.radius), options);
    d.balance(coords, ids);
    const mpi::domain_stats moved = d.stats();
    kill_hook(rank);
    d.build(coords, ids);
    const mpi::domain_stats built = d.stats();
    clock.lap_ms();
    rank_figures mine;
    // Files keep each pair once (i < j), but .npz holds the whole lists, as the serial tool.
    const std::string ext = lower_extension(a.output);
    const io::pair_filter filter = ext == ".npz" ? io::pair_filter::all : io::pair_filter::upper;
    global_rows<T> rows;
    {
        const csr<T> lists = d.neighbor_lists(true);
        mine.lists_ms = clock.lap_ms();
        mine.pairs = double(upper_pairs(d, lists));
        if (!a.output.empty()) rows = rows_of(d, lists, filter, ext != ".npy");
    }  // the lists are freed before the write
    mine.particles = double(d.local_size());
    mine.ghosts = double(d.ghost_size());
    mine.decompose_ms = moved.decompose_ms;
    mine.migrate_ms = moved.migrate_ms;
    mine.migrate_bytes = double(moved.migrate_bytes);
    mine.halo_ms = built.halo_ms;
    mine.grid_ms = built.grid_ms;
    mine.halo_bytes = double(built.halo_bytes);
    if (!a.output.empty()) {
        MPI_Barrier(comm);  // the write's time starts when every rank's search is done
        clock.lap_ms();
        write_distributed(comm, a.output, std::move(rows), in.total, filter);
        report.write_ms = clock.lap_ms();
    }
    report.per_rank.assign(std::size_t(report.ranks), {});
    MPI_Gather(&mine, figure_count, MPI_DOUBLE, report.per_rank.data(), figure_count, MPI_DOUBLE, 0, comm);
    for (const rank_figures& f : report.per_rank) {
        report.pairs += std::uint64_t(f.pairs);
        report.search_ms = std::max(report.search_ms, f.decompose_ms + f.migrate_ms + f.halo_ms + f.grid_ms + f.lists_ms);
    }
}

void print_report(const query_args& a, const mpi_report& r) {
    const std::string input = a.input.empty() ? a.generate : a.input;
    if (a.json) {
        nlohmann::ordered_json j;
        j["input"] = input;
        j["ranks"] = r.ranks;
        j["points"] = r.points;
        j["dimension"] = r.dimension;
        j["precision"] = r.precision;
        j["radius"] = a.radius;
        j["periodic"] = a.periodic.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(parse_periodic(a.periodic));
        j["pairs"] = r.pairs;
        j["output"] = a.output.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(a.output);
        j["time_ms"] = {{"read", r.read_ms}, {"search", r.search_ms}, {"write", r.write_ms}};
        nlohmann::ordered_json ranks = nlohmann::ordered_json::array();
        for (std::size_t k = 0; k < r.per_rank.size(); ++k) {
            const rank_figures& f = r.per_rank[k];
            ranks.push_back({{"rank", k},
                             {"particles", std::uint64_t(f.particles)},
                             {"ghosts", std::uint64_t(f.ghosts)},
                             {"pairs", std::uint64_t(f.pairs)},
                             {"exchange_ms", {{"decompose", f.decompose_ms}, {"migrate", f.migrate_ms}, {"halo", f.halo_ms}}},
                             {"local_ms", {{"grid", f.grid_ms}, {"lists", f.lists_ms}}},
                             {"bytes_sent", {{"migrate", std::uint64_t(f.migrate_bytes)}, {"halo", std::uint64_t(f.halo_bytes)}}}});
        }
        j["per_rank"] = ranks;
        std::cout << j.dump(2) << '\n';
        return;
    }
    std::printf("points     %llu (%dD, %s) from %s, on %d ranks\n", static_cast<unsigned long long>(r.points),
                r.dimension, r.precision.c_str(), input.c_str(), r.ranks);
    std::printf("radius     %g\n", a.radius);
    std::printf("pairs      %llu (i < j)\n", static_cast<unsigned long long>(r.pairs));
    std::printf("rank  particles     ghosts        pairs  exchange ms  local ms\n");
    for (std::size_t k = 0; k < r.per_rank.size(); ++k) {
        const rank_figures& f = r.per_rank[k];
        std::printf("%4zu %10.0f %10.0f %12.0f %12.1f %9.1f\n", k, f.particles, f.ghosts, f.pairs,
                    f.decompose_ms + f.migrate_ms + f.halo_ms, f.grid_ms + f.lists_ms);
    }
    std::printf("time       read %.1f ms, search %.1f ms (slowest rank), write %.1f ms\n", r.read_ms, r.search_ms,
                r.write_ms);
    if (!a.output.empty()) std::printf("output     %s\n", a.output.c_str());
}

void run(const query_args& a) {
    MPI_Comm comm = MPI_COMM_WORLD;
    int rank = 0;
    mpi_report report;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &report.ranks);
    stopwatch clock;
    require_same_files(comm, a);
    const input_slice in = read_input_slice(comm, a);
    check_periodic(a.periodic.empty() ? std::vector<double>{} : parse_periodic(a.periodic), in.points.dimension, a.radius);
    // Output files number points in 32 bits, as the single-process tool's lists do.
    mpi::throw_if_any(comm, a.output.empty() || in.total <= UINT32_MAX ? "" : "the output file cannot number " +
                                                                                  std::to_string(in.total) + " points (at most 2^32)");
    report.read_ms = clock.lap_ms();
    report.points = in.total;
    report.dimension = in.points.dimension;
    report.precision = io::to_string(in.points.type());
    io::visit_points(in.points, [&]<class T, int D>(std::span<const T>) { search<T, D>(comm, a, in, report); });
    if (rank == 0) print_report(a, report);
}

}  // namespace

void run_query_mpi(const query_args& a) {
    int code = 0;
    {
        mpi_session session;
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        // Collective errors are the same on every rank: rank 0 prints them once, and the
        // others exit only after it did (MPI_Finalize waits for every rank).
        try {
            check_usage(a);
            check_mpi_usage(a);
            run(a);
        } catch (const mpi::collective_error& e) {
            if (rank == 0) std::fprintf(stderr, "frnn: error: %s\n", e.what());
            code = 1;
        } catch (const CLI::ParseError& e) {
            // From the options and the file's header: the same on every rank.
            if (rank == 0) std::fprintf(stderr, "frnn: %s\n", e.what());
            code = 2;
        } catch (const std::exception& e) {
            // Thrown on this rank alone: the others may wait for it in a collective for ever.
            std::fprintf(stderr, "frnn: error: rank %d: %s\n", rank, e.what());
            std::fflush(stderr);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        std::fflush(stderr);
    }
    if (code) throw exit_status{code, {}};
}

}  // namespace frnn::app
