// The options of `frnn query` and the helpers its single-process path (cmd_query.cpp) and its
// distributed path under mpirun (query_mpi.cpp) share.
#pragma once
#include <cctype>
#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

#include "frnn/detail/stopwatch.hpp"
#include "frnn/io/point_set.hpp"
#include "frnn/io/read.hpp"

namespace frnn::app {

struct query_args {
    std::string input, output, queries, generate, grid = "auto", periodic;
    /// --cell (lattice vectors as rows, comma-separated) and --pbc (a flag per vector).
    std::string cell, pbc;
    /// --radius as given: a number (radius), or a .npy of one radius per point (radius_file).
    std::string radius_text, radius_file, rule = "gather";
    double radius = 0, cell_size = 0;
    std::size_t knn = 0;
    int threads = 0, dim = 3;
    std::uint64_t seed = 42;
    std::string backend = "cpu";
    bool self = false, json = false;
};

using detail::stopwatch;

/// The extension of `file`, lower case, with its dot (".npy").
inline std::string lower_extension(const std::string& file) {
    std::string ext = std::filesystem::path(file).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// --periodic LX,LY[,LZ] as lengths; CLI::ValidationError when malformed.
std::vector<double> parse_periodic(const std::string& text);
/// The points of --generate (lattice:N or uniform:N), as `frnn bench` draws its workloads.
io::point_set generate_points(const std::string& spec, int dim, std::uint64_t seed);
/// Slice `part` of `parts` of those points (io::slice_start's rows), drawn alone.
io::point_slice generate_slice(const std::string& spec, int dim, std::uint64_t seed, std::uint64_t part,
                               std::uint64_t parts);
/// --radius: a positive number into a.radius, or a .npy file into a.radius_file;
/// CLI::ValidationError otherwise.
void parse_radius(query_args& a);
/// Options that do not go together, unknown extensions: CLI::ValidationError (exit 2).
void check_usage(const query_args& a);
/// One box length per dimension, each at least 2 * radius: CLI::ValidationError otherwise.
void check_periodic(const std::vector<double>& periodic, int dimension, double radius);
/// Options that do not go with --cell, --pbc without --cell: CLI::ValidationError.
void check_lattice_usage(const query_args& a);
/// The query in a periodic cell of any shape (query_lattice.cpp): pairs with their shifts.
void run_lattice_query(const query_args& a, const io::point_set& data, double read_ms);

}  // namespace frnn::app
