// Writers of neighbor results and arrays: .npy (pairs as int64 (M,2), or any numeric array),
// .csv (i,j,distance with a header line) and .npz (CSR lists: offsets, indices, distances).
// Every writer writes to a temporary file in the target's folder and renames it over the
// target only when everything was written, so a failure never leaves a partial file.
// Cost: O(output size), streamed (no second copy of the result in memory).
// Not part of the public API. Thread safety: free functions; distinct targets may be written
// concurrently.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>

#include "frnn/csr.hpp"

namespace frnn::io {

/// Which entries of neighbor lists become pairs.
enum class pair_filter {
    all,    ///< every (row, neighbor) entry
    upper,  ///< only entries with neighbor >= row: each unordered pair once (plus self pairs)
};

/// Number of pairs `filter` keeps from `lists`.
template <class T>
std::uint64_t count_pairs(const csr<T>& lists, pair_filter filter);

/// int64 array of shape (M, 2): (row, neighbor) in the order of the lists.
template <class T>
void write_pairs_npy(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter);
/// Header "i,j,distance", then one line per pair; distances round-trip exactly. Needs distances.
template <class T>
void write_pairs_csv(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter);
/// Zip archive (stored, uncompressed) of offsets.npy (int64, rows+1), indices.npy (int64) and
/// distances.npy (float64), readable with numpy.load. Needs distances.
template <class T>
void write_csr_npz(const std::filesystem::path& file, const csr<T>& lists);
/// Chooses the writer by extension: .npy and .csv write pairs, .npz writes the lists.
template <class T>
void write_neighbors(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter);
/// True when write_neighbors knows the extension of `file`.
bool is_neighbor_output(const std::filesystem::path& file);

/// Any array of float, double, int32, int64, uint32 or uint64 values, C order; the product of
/// `shape` must equal data.size().
template <class T>
void write_npy(const std::filesystem::path& file, std::span<const T> data,
               std::span<const std::uint64_t> shape);
/// A 1-D array.
template <class T>
void write_npy(const std::filesystem::path& file, std::span<const T> data) {
    const std::uint64_t shape[1] = {data.size()};
    write_npy<T>(file, data, shape);
}

}  // namespace frnn::io
