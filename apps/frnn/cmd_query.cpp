// `frnn query`: the neighbor pairs of a point file (or of a generated point set), written as
// .npy pairs, .csv lines or .npz CSR lists, with a summary on stdout (text or JSON).
// Usage errors throw CLI::ValidationError (exit 2); bad input throws frnn::error (exit 1).
#ifdef FRNN_IO_AVAILABLE
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <vector>

#include "command.hpp"
#include "query_args.hpp"
#include "query_mpi.hpp"
#include "validators.hpp"
#include "frnn/bench/workloads.hpp"
#include "frnn/grid.hpp"
#include "frnn/io/read.hpp"
#include "frnn/io/write.hpp"
#ifdef FRNN_VULKAN_AVAILABLE
#include "frnn/vulkan.hpp"
#endif

namespace frnn::app {

std::vector<double> parse_periodic(const std::string& text) {
    std::vector<double> lengths;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma - start);
        double v = 0;
        const auto r = std::from_chars(item.data(), item.data() + item.size(), v);
        if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size() ||
            !std::isfinite(v) || v < 0)
            throw CLI::ValidationError("--periodic", "'" + item +
                                                         "' is not a box length >= 0 (expected LX,LY[,LZ]; 0 for an open axis)");
        lengths.push_back(v);
        if (comma == std::string::npos) return lengths;
        start = comma + 1;
    }
}

// Built-in point sets: the generators of the benchmark workloads (W1 and W4 are lattice:N with
// --dim 3 and 2, W2 uniform:N), so with the default seed the same points as `frnn bench`.
io::point_slice generate_slice(const std::string& spec, int dim, std::uint64_t seed, std::uint64_t part,
                               std::uint64_t parts) {
    const std::size_t colon = spec.find(':');
    const std::string kind = spec.substr(0, colon);
    std::uint64_t n = 0;
    const char* first = spec.data() + (colon == std::string::npos ? spec.size() : colon + 1);
    const auto r = std::from_chars(first, spec.data() + spec.size(), n);
    if ((kind != "lattice" && kind != "uniform") || colon == std::string::npos || n == 0 ||
        r.ec != std::errc() || r.ptr != spec.data() + spec.size())
        throw CLI::ValidationError("--generate", "'" + spec +
                                                     "': expected lattice:N or uniform:N with N > 0");
    const double count = kind == "lattice" ? std::pow(double(n), dim) : double(n);
    if (count > 1e9) throw CLI::ValidationError("--generate", "'" + spec + "' asks for too many points");

    io::point_slice s;
    s.total = std::uint64_t(count);
    s.first = io::slice_start(s.total, part, parts);
    const std::uint64_t end = io::slice_start(s.total, part + 1, parts);
    s.points.dimension = dim;
    s.points.coords = kind == "lattice" ? bench::jittered_lattice<double>(n, dim, seed, s.first, end)
                                        : bench::uniform_cube<double>(n, dim, seed, s.first, end);
    return s;
}

io::point_set generate_points(const std::string& spec, int dim, std::uint64_t seed) {
    return generate_slice(spec, dim, seed, 0, 1).points;
}

void parse_radius(query_args& a) {
    const std::string& text = a.radius_text;
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (!text.empty() && r.ec == std::errc() && r.ptr == text.data() + text.size()) {
        if (!(v > 0) || !std::isfinite(v)) throw CLI::ValidationError("--radius", "must be a finite number > 0, got " + text);
        a.radius = v;
        return;
    }
    if (lower_extension(text) != ".npy")
        throw CLI::ValidationError("--radius", "'" + text + "' is neither a number nor a .npy file of one radius per point");
    a.radius_file = text;
}

void check_usage(const query_args& a) {
    if (a.input.empty() == a.generate.empty())
        throw CLI::ValidationError("INPUT", "give exactly one of an INPUT file or --generate");
    if (!a.input.empty() && !io::is_point_file(a.input))
        throw CLI::ValidationError("INPUT", "'" + a.input +
                                                "': unknown extension (expected .npy, .csv, .txt, .xyz or .ply)");
    if (!a.queries.empty() && !io::is_point_file(a.queries))
        throw CLI::ValidationError("--queries", "'" + a.queries +
                                                    "': unknown extension (expected .npy, .csv, .txt, .xyz or .ply)");
    if (!a.output.empty() && !io::is_neighbor_output(a.output))
        throw CLI::ValidationError("--output", "'" + a.output + "': unknown extension (expected .npy, .csv or .npz)");
    if (!std::isfinite(a.radius))
        throw CLI::ValidationError("--radius", "must be finite");
    if (a.cell_size != 0 && (a.cell_size > a.radius || a.cell_size < a.radius / 4))
        throw CLI::ValidationError("--cell-size", "must lie between radius/4 and the radius");
    if (a.self && !a.queries.empty())
        throw CLI::ValidationError("--self", "does not apply with --queries (query points are not data points)");
    if (!a.radius_file.empty() && !a.queries.empty())
        throw CLI::ValidationError("--queries", "not with a radius per point (--radius FILE): query points would need "
                                               "radii of their own (the C++ and Python APIs take them)");
    if (!a.radius_file.empty() && a.backend == "vulkan")
        throw CLI::ValidationError("--backend", "the Vulkan backend takes one radius; a radius per point (--radius FILE) "
                                               "runs on the CPU");
    if (!a.radius_file.empty() && a.cell_size != 0)
        throw CLI::ValidationError("--cell-size", "not with a radius per point: cells are sized from the radii");
}

namespace {
std::string shortest(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.15g", v);
    return buf;
}
}  // namespace

void check_periodic(const std::vector<double>& periodic, int dimension, double radius) {
    if (periodic.empty()) return;
    if (periodic.size() != std::size_t(dimension))
        throw CLI::ValidationError("--periodic", "needs " + std::to_string(dimension) + " box lengths for " +
                                                     std::to_string(dimension) + "-D points, got " +
                                                     std::to_string(periodic.size()));
    for (std::size_t a = 0; a < periodic.size(); ++a)
        if (periodic[a] != 0 && periodic[a] < 2 * radius)
            throw CLI::ValidationError("--periodic", "the box length " + shortest(periodic[a]) + " on axis " +
                                                         std::to_string(a) + " is less than 2 * radius (" +
                                                         shortest(2 * radius) + "); 0 leaves an axis open");
}

namespace {

// What the summary reports.
struct query_report {
    std::size_t points = 0, query_points = 0, slots = 0, occupied = 0, max_neighbors = 0;
    int dimension = 3, threads = 1;
    std::string precision, grid;
    double cell_size = 0, mean_neighbors = 0;
    std::uint64_t pairs = 0;
    double read_ms = 0, build_ms = 0, query_ms = 0, write_ms = 0;
};

// k-nearest rows come sorted by distance; files list every row by neighbor index.
template <class T>
void sort_rows_by_index(csr<T>& lists) {
    std::vector<std::pair<std::uint32_t, T>> row;
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        const std::uint64_t b = lists.offsets[i], e = lists.offsets[i + 1];
        row.clear();
        for (std::uint64_t k = b; k < e; ++k) row.emplace_back(lists.indices[k], lists.distances[k]);
        std::sort(row.begin(), row.end());
        for (std::uint64_t k = b; k < e; ++k) std::tie(lists.indices[k], lists.distances[k]) = row[k - b];
    }
}

void print_report(const query_args& a, const query_report& r) {
    const std::string input = a.input.empty() ? a.generate : a.input;
    if (a.json) {
        nlohmann::ordered_json j;
        j["input"] = input;
        j["points"] = r.points;
        j["dimension"] = r.dimension;
        j["precision"] = r.precision;
        if (!a.queries.empty()) {
            j["queries"] = a.queries;
            j["query_points"] = r.query_points;
        }
        j["radius"] = a.radius;  // the largest, with a radius per point
        if (!a.radius_file.empty()) {
            j["radius_file"] = a.radius_file;
            j["rule"] = a.rule;
        }
        j["knn"] = a.knn;
        j["self"] = a.self;
        j["pairs"] = r.pairs;
        j["mean_neighbors"] = r.mean_neighbors;
        j["max_neighbors"] = r.max_neighbors;
        j["grid"] = r.grid;
        j["slots"] = r.slots;
        j["occupied_slots"] = r.occupied;
        j["cell_size"] = r.cell_size;
        j["threads"] = r.threads;
        j["output"] = a.output.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(a.output);
        j["time_ms"] = {{"read", r.read_ms}, {"build", r.build_ms}, {"query", r.query_ms}, {"write", r.write_ms}};
        std::cout << j.dump(2) << '\n';
        return;
    }
    std::printf("points     %zu (%dD, %s) from %s\n", r.points, r.dimension, r.precision.c_str(), input.c_str());
    if (!a.queries.empty()) std::printf("queries    %zu from %s\n", r.query_points, a.queries.c_str());
    const std::string per_point = a.radius_file.empty() ? "" : " (the largest of " + a.radius_file + ", rule " + a.rule + ")";
    std::printf("radius     %g%s%s%s\n", a.radius, per_point.c_str(),
                a.knn ? (", at most " + std::to_string(a.knn) + " nearest").c_str() : "", a.self ? ", self pairs included" : "");
    std::printf("pairs      %llu%s\n", static_cast<unsigned long long>(r.pairs),
                a.queries.empty() && a.knn == 0 ? " (i < j)" : "");
    std::printf("neighbors  mean %.2f, max %zu per %s point\n", r.mean_neighbors, r.max_neighbors,
                a.queries.empty() ? "data" : "query");
    if (a.backend == "vulkan")
        std::printf("grid       %s, %zu slots, cell size %g, on the Vulkan device\n", r.grid.c_str(), r.slots,
                    r.cell_size);
    else
        std::printf("grid       %s, %zu slots (%zu occupied), cell size %g, %d threads\n", r.grid.c_str(), r.slots,
                    r.occupied, r.cell_size, r.threads);
    std::printf("time       read %.1f ms, build %.1f ms, query %.1f ms, write %.1f ms\n", r.read_ms, r.build_ms,
                r.query_ms, r.write_ms);
    if (!a.output.empty()) std::printf("output     %s\n", a.output.c_str());
}

// Writes the output file and fills the pair statistics of the report.
template <class T>
void finish_lists(const query_args& a, const csr<T>& lists, query_report& r, stopwatch& clock) {
    // Without --queries or --knn (or gather radii per point) the lists are symmetric: files
    // keep each pair once (i <= j).
    const bool mutual = a.queries.empty() && a.knn == 0 && (a.radius_file.empty() || a.rule == "symmetric");
    const io::pair_filter filter = mutual ? io::pair_filter::upper : io::pair_filter::all;
    if (!a.output.empty()) io::write_neighbors(a.output, lists, filter);
    r.write_ms = clock.lap_ms();
    r.pairs = io::count_pairs(lists, filter);
    for (std::size_t i = 0; i < lists.rows(); ++i)
        r.max_neighbors = std::max<std::size_t>(r.max_neighbors, lists.row(i).size());
    r.mean_neighbors = lists.rows() ? double(lists.size()) / double(lists.rows()) : 0.0;
}

// The same query on the Vulkan device: float input in float; double input in double (the
// device finds float candidates, the host decides them in double; see docs/VULKAN.md).
#ifdef FRNN_VULKAN_AVAILABLE
template <class T>
void query_on_vulkan_as(const query_args& a, io::point_set& data, io::point_set& queries,
                        const std::vector<double>& periodic, query_report& r, stopwatch& clock) {
    if (!a.queries.empty()) queries.convert_to(data.type());
    grid_options options;
    options.kind = parse_grid_kind(a.grid);
    options.cell_size = a.cell_size;
    options.periodic = periodic;
    list_options lists_options;
    lists_options.distances = true;
    lists_options.self = a.self;
    lists_options.order = row_order::index;
    vulkan::context ctx;
    const auto& xyz = std::get<std::vector<T>>(data.coords);
    const std::vector<T> none;
    const auto& q = a.queries.empty() ? none : std::get<std::vector<T>>(queries.coords);
    auto found = vulkan::search(ctx, std::span<const T>(xyz), data.dimension, T(a.radius), options, lists_options,
                                std::span<const T>(q), a.knn);
    if (a.knn) sort_rows_by_index(found.lists);
    clock.lap_ms();
    r.build_ms = found.build_ms;
    r.query_ms = found.query_ms;
    r.points = data.size();
    r.dimension = data.dimension;
    r.precision = std::is_same_v<T, float> ? "float (vulkan)" : "double (vulkan: float candidates, decided in double)";
    r.grid = std::string(to_string(found.kind)) + " (vulkan)";
    r.slots = found.slots;
    r.cell_size = a.cell_size > 0 ? a.cell_size : a.radius;
    r.threads = 0;
    finish_lists(a, found.lists, r, clock);
}
#endif

void query_on_vulkan(const query_args& a, io::point_set& data, io::point_set& queries,
                     const std::vector<double>& periodic, query_report& r, stopwatch& clock) {
#ifdef FRNN_VULKAN_AVAILABLE
    if (data.type() == io::precision::f32) query_on_vulkan_as<float>(a, data, queries, periodic, r, clock);
    else query_on_vulkan_as<double>(a, data, queries, periodic, r, clock);
#else
    (void)a, (void)data, (void)queries, (void)periodic, (void)r, (void)clock;
    throw error("this frnn was built without the Vulkan backend (it needs libvulkan-dev and glslc at build time)");
#endif
}

void run_query(query_args a) {
    parse_radius(a);
    check_lattice_usage(a);
    if (launched_by_mpirun()) return run_query_mpi(a);
    check_usage(a);
    if (!a.cell.empty()) {
        stopwatch read_clock;
        const io::point_set atoms =
            a.input.empty() ? generate_points(a.generate, a.dim, a.seed) : io::read_points(a.input, a.threads);
        return run_lattice_query(a, atoms, read_clock.lap_ms());
    }
    std::vector<double> radii;
    if (!a.radius_file.empty()) {
        radii = io::read_npy_values(a.radius_file);
        a.radius = 0;
        for (double v : radii) a.radius = std::isfinite(v) ? std::max(a.radius, v) : a.radius;
    }
    const std::vector<double> periodic = a.periodic.empty() ? std::vector<double>{} : parse_periodic(a.periodic);
    query_report r;
    stopwatch clock;

    io::point_set data = a.input.empty() ? generate_points(a.generate, a.dim, a.seed) : io::read_points(a.input, a.threads);
    io::point_set queries;
    if (!a.queries.empty()) {
        queries = io::read_points(a.queries, a.threads);
        if (queries.size() > 0 && queries.dimension != data.dimension)
            throw error(a.queries + ": " + std::to_string(queries.dimension) + "-D points, but the data points are " +
                        std::to_string(data.dimension) + "-D");
        queries.dimension = data.dimension;
        queries.convert_to(data.type());  // distances in the data's precision
    }
    check_periodic(periodic, data.dimension, a.radius);
    r.read_ms = clock.lap_ms();
    r.query_points = a.queries.empty() ? 0 : queries.size();
    if (a.backend == "vulkan") {
        query_on_vulkan(a, data, queries, periodic, r, clock);
        print_report(a, r);
        return;
    }

    io::visit_points(data, [&]<class T, int D>(std::span<const T> xyz) {
        grid_options options;
        options.kind = parse_grid_kind(a.grid);
        options.cell_size = a.cell_size;
        options.periodic = periodic;
        options.threads = a.threads;
        options.rule = parse_radius_rule(a.rule);
        grid<T, D> g;
        if (radii.empty()) {
            g.build(xyz, T(a.radius), options);
        } else {
            if (radii.size() != xyz.size() / D)
                throw error(a.radius_file + ": " + std::to_string(radii.size()) + " radii for " +
                            std::to_string(xyz.size() / D) + " points");
            const std::vector<T> typed(radii.begin(), radii.end());
            try {
                g.build(xyz, std::span<const T>(typed), options);
            } catch (const error& e) {
                throw error(a.radius_file + ": " + e.what());
            }
        }
        r.build_ms = clock.lap_ms();

        list_options lists_options;
        lists_options.distances = true;
        lists_options.self = a.self;
        lists_options.order = row_order::index;
        csr<T> lists;
        if (a.queries.empty()) {
            lists = a.knn ? g.nearest(a.knn, lists_options) : g.neighbor_lists(lists_options);
        } else {
            const auto& q = std::get<std::vector<T>>(queries.coords);
            lists = a.knn ? g.query_nearest(q, a.knn, lists_options) : g.query(q, lists_options);
        }
        if (a.knn) sort_rows_by_index(lists);
        r.query_ms = clock.lap_ms();

        r.points = g.size();
        r.dimension = D;
        r.precision = io::to_string(data.type());
        r.grid = to_string(g.kind());
        r.slots = g.slot_count();
        r.occupied = g.occupied_slots();
        r.cell_size = g.cell_size();
        r.threads = g.threads();
        finish_lists(a, lists, r, clock);
    });
    print_report(a, r);
}

const register_command query_command{"query", [](CLI::App& app) {
    auto args = std::make_shared<query_args>();
    CLI::App* cmd = app.add_subcommand(
        "query", "Find all neighbor pairs within a radius in a point file (.npy, .csv/.txt/.xyz, .ply)");
    cmd->add_option("INPUT", args->input, "Point file: .npy (float32/float64, (N,2) or (N,3)), .csv/.txt/.xyz, .ply");
    cmd->add_option("--radius,-r", args->radius_text,
                    "Search radius: pairs with distance <= R; or a .npy of one radius per point (N,) "
                    "(pairs by --rule)")
        ->required();
    cmd->add_option("--rule", args->rule,
                    "With a radius per point: gather (j within r_i of i) or symmetric (within max(r_i, r_j))")
        ->check(CLI::IsMember({"gather", "symmetric"}));
    cmd->add_option("--output,-o", args->output,
                    "Output file: .npy (int64 pairs (M,2)), .csv (i,j,distance) or .npz (CSR lists)");
    cmd->add_option("--queries", args->queries, "Query points (same formats): pairs are (query index, data index)");
    cmd->add_option("--generate", args->generate,
                    "Use a built-in point set instead of INPUT, drawn as frnn bench draws its workloads: "
                    "lattice:N (N^dim jittered lattice points, spacing 1: W1, or W4 with --dim 2) or "
                    "uniform:N (N uniform points at density 1: W2)");
    cmd->add_option("--dim", args->dim, "Dimension of --generate points")->check(CLI::IsMember({2, 3}));
    cmd->add_option("--seed", args->seed, "Random seed of --generate");
    cmd->add_option("--grid", args->grid, "Grid kind")->check(CLI::IsMember({"auto", "uniform", "hash"}));
    cmd->add_option("--cell-size", args->cell_size, "Cell edge, between radius/4 and radius (default: radius)")
        ->check(positive_number);
    cmd->add_option("--periodic", args->periodic,
                    "Periodic box [0,LX)x[0,LY)[x[0,LZ)]: LX,LY[,LZ]; a length of 0 leaves that axis open (10,0,10)");
    cmd->add_option("--cell", args->cell,
                    "A periodic cell of any shape, for atoms: the lattice vectors as rows, ax,ay,az,bx,by,bz,cx,cy,cz "
                    "(ax,ay,bx,by in 2D); triclinic and smaller than the radius are fine. Pairs come once per "
                    "periodic image, with their shift S (output .npy rows i,j,S or .csv i,j,S...,distance)");
    cmd->add_option("--pbc", args->pbc, "With --cell: periodic along each lattice vector, e.g. 1,1,0 (default: all)");
    cmd->add_option("--knn", args->knn, "Keep at most K nearest neighbors within the radius per point")
        ->check(positive_number);
    cmd->add_flag("--self", args->self, "Include each point as its own neighbor (pair (i,i), distance 0)");
    cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--json", args->json, "Print the summary as one JSON object");
    cmd->add_option("--backend", args->backend, "Where the search runs: cpu, or vulkan (float on the device; double input decided in double)")
        ->check(CLI::IsMember({"cpu", "vulkan"}));
    cmd->callback([args] { run_query(*args); });
}};

}  // namespace
}  // namespace frnn::app
#endif
