// The neighbor files of write_neighbors (.npy pairs, .csv pairs, .npz lists), cut so that any
// block of consecutive rows is encoded on its own: the file is, for each member m, frame.before[m]
// followed by the encodings of m's row blocks in row order, then frame.after. .npy and .csv
// have one member; .npz has three (offsets, indices, distances), each a stored zip member.
// The single-process writers stream blocks of rows through this; the ranks of a distributed
// query each encode their own rows and write them in place (apps/frnn/mpi_output.cpp), so both
// write the same bytes.
// Not part of the public API. Thread safety: free functions.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "frnn/csr.hpp"
#include "frnn/io/write.hpp"

namespace frnn::io {

enum class neighbor_format { pairs_npy, pairs_csv, lists_npz };

/// The format write_neighbors picks for `file`'s extension; an error naming the file otherwise.
neighbor_format neighbor_format_of(const std::filesystem::path& file);
/// Members of a format's file: 1, or 3 for .npz.
int member_count(neighbor_format f);
/// Whether the format writes distances (the lists must then have them).
bool needs_distances(neighbor_format f);

/// How a block's rows are numbered in the file: row i of the lists is file row first_row + i,
/// and the file's lists hold entries_before entries before that row (.npz offsets).
struct row_numbering {
    std::uint64_t first_row = 0;
    std::uint64_t entries_before = 0;
};

/// Member m's bytes for rows [b, e) of `lists` (neighbors given as file row numbers) into
/// `bytes`, replacing its contents (a buffer reused from block to block stays in cache); .npy
/// and .csv keep the entries `filter` keeps, .npz every entry. With `closes` (e is the file's
/// last row), also what follows that row: the final offset of .npz.
template <class T>
void encode_rows(std::string& bytes, neighbor_format f, int member, const csr<T>& lists, std::size_t b, std::size_t e,
                 row_numbering at, pair_filter filter, bool closes);

/// The bytes encode_rows writes for member m of `rows` rows holding `entries` list entries, of
/// which `kept` pass the filter, summed over the blocks (`closes` as for the last one), where
/// the format's values have one size (.npy, .npz); nullopt for .csv, whose lines vary.
std::optional<std::uint64_t> encoded_size(neighbor_format f, int member, std::uint64_t rows, std::uint64_t entries,
                                          std::uint64_t kept, bool closes);

/// CRC-32 (zlib's) and length of some bytes: what the .npz frame needs of a member's body.
struct checksum {
    std::uint32_t crc = 0;
    std::uint64_t bytes = 0;
};
checksum checksum_of(std::string_view bytes);
/// The checksum of the bytes of `a` followed by `bytes`.
checksum extended(checksum a, std::string_view bytes);
/// The checksum of the bytes of `a` followed by those of `b` (slower than extended: zlib's
/// crc32_combine, for parts whose bytes are elsewhere).
checksum concatenate(checksum a, checksum b);

struct neighbor_frame {
    std::vector<std::string> before;  ///< one per member; their lengths never depend on the CRCs
    std::string after;
};

/// The frame of a file of `rows` rows and `entries` entries (pairs kept, for .npy and .csv;
/// list entries, for .npz). .npz reads body_crcs, the CRC of each member's body (zeros if
/// empty), and fails, naming `file`, when the archive would exceed 4 GiB (no zip64).
neighbor_frame frame_of(neighbor_format f, const std::filesystem::path& file, std::uint64_t rows, std::uint64_t entries,
                        std::span<const std::uint32_t> body_crcs = {});

}  // namespace frnn::io
