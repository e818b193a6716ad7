// Chooses the neighbor writer by file extension.
#include "frnn/io/write.hpp"
#include "util.hpp"

namespace frnn::io {

bool is_neighbor_output(const std::filesystem::path& file) {
    const std::string ext = detail::lower_extension(file);
    return ext == ".npy" || ext == ".csv" || ext == ".npz";
}

template <class T>
void write_neighbors(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    const std::string ext = detail::lower_extension(file);
    if (ext == ".npy") return write_pairs_npy(file, lists, filter);
    if (ext == ".csv") return write_pairs_csv(file, lists, filter);
    if (ext == ".npz") return write_csr_npz(file, lists);
    detail::fail(file.string(),
                 "unknown output extension '" + ext + "' (expected .npy, .csv or .npz)");
}

template void write_neighbors(const std::filesystem::path&, const csr<float>&, pair_filter);
template void write_neighbors(const std::filesystem::path&, const csr<double>&, pair_filter);

}  // namespace frnn::io
