// Chooses the point reader by file extension.
#include "frnn/io/read.hpp"
#include "util.hpp"

namespace frnn::io {

bool is_point_file(const std::filesystem::path& file) {
    const std::string ext = detail::lower_extension(file);
    return ext == ".npy" || ext == ".csv" || ext == ".txt" || ext == ".xyz" || ext == ".ply";
}

point_set read_points(const std::filesystem::path& file, int threads) {
    const std::string ext = detail::lower_extension(file);
    if (ext == ".npy") return read_npy_points(file);
    if (ext == ".ply") return read_ply_points(file);
    if (is_point_file(file)) return read_text_points(file, threads);
    detail::fail(file.string(), "unknown point file extension '" + ext +
                                    "' (expected .npy, .csv, .txt, .xyz or .ply)");
}

}  // namespace frnn::io
