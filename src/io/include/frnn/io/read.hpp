// Readers of point files: .npy (float32/float64, shape (N,2) or (N,3), C or Fortran order),
// .csv/.txt/.xyz (2 or 3 numeric columns separated by commas or white space, '#' comments,
// one optional header line) and .ply (ascii or binary, vertex x y [z]).
// Each reader is O(file size) and keeps one copy of the points (text and ply also hold the
// file in memory while parsing). Every malformed input throws frnn::error naming the file and
// the line (text formats) or byte / element index, and what was wrong; a non-finite coordinate
// names its point index. Zero points is a valid result.
// Not part of the public API. Thread safety: free functions without shared state.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "frnn/io/point_set.hpp"

namespace frnn::io {

/// Reads a point file, choosing the format by its extension (case-insensitive). Text files of
/// a few MiB and more are parsed in parts on `threads` threads (0: default_thread_count()),
/// with the points and the first error of a serial parse.
point_set read_points(const std::filesystem::path& file, int threads = 0);
/// True when read_points knows the extension of `file`.
bool is_point_file(const std::filesystem::path& file);

point_set read_npy_points(const std::filesystem::path& file);

/// One value per row of a .npy of shape (N,) or (N, 1), float32 or float64 (radii per point);
/// throws frnn::error naming the file for anything else. Values are not checked here.
std::vector<double> read_npy_values(const std::filesystem::path& file);
/// Rows [first, first + points.size()) of an .npy point file of `total` rows.
struct point_slice {
    point_set points;
    std::uint64_t first = 0, total = 0;
};
/// The first row of slice `part` of `parts` nearly equal slices of n rows: n * part / parts
/// (computed without overflowing n * part).
inline std::uint64_t slice_start(std::uint64_t n, std::uint64_t part, std::uint64_t parts) {
    return n / parts * part + n % parts * part / parts;
}
/// Slice `part` of `parts` (rows slice_start(total, part, parts) up to that of part + 1): reads
/// the header and only those rows' bytes, so that each MPI rank reads its own share of a file.
/// Checks the whole file's header and size as read_npy_points does; a non-finite coordinate is
/// named by its index in the file.
point_slice read_npy_slice(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts);
point_set read_text_points(const std::filesystem::path& file, int threads = 0);
point_set read_ply_points(const std::filesystem::path& file);
/// Vertex slice `part` of `parts` of a binary .ply whose elements up to the vertices have no
/// list (their rows then lie at fixed offsets): reads the header and only those rows' bytes,
/// and gives the points and the first error that read_ply_points gives for them (vertex
/// numbers in the file). nullopt for any other .ply (ascii, lists, a header beyond 64 KiB or
/// in error, data ending before the vertices): read it whole.
std::optional<point_slice> read_ply_slice(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts);

// A text point file read in parts (one per MPI rank), giving the points and the first error
// that read_text_points gives: part k of P holds the lines that start in bytes
// [slice_start(S, k, P), slice_start(S, k + 1, P)) of the file's S bytes. A part is summed up
// without parsing its numbers (summarize_text_part); the summaries of the parts before it
// settle what its lines are parsed against (context_after): line and point numbers, whether a
// header may still come, and the first data line's columns.

/// What a part's lines tell the parts after it.
struct text_part_summary {
    std::uint64_t lines = 0;     ///< lines in the part
    std::uint64_t nonblank = 0;  ///< lines left after removing comments and blanks
    /// The first two of those: line number within the part (from 1), number of fields, and
    /// (the first) whether none of its fields is a number, as a header's.
    std::uint64_t first_line = 0, first_fields = 0, first_is_header = 0;
    std::uint64_t second_line = 0, second_fields = 0;
};
/// Where the parse of a text file stands after some of its lines.
struct text_context {
    std::uint64_t lines = 0;            ///< lines read
    std::uint64_t points = 0;           ///< points read
    bool any_nonblank = false;          ///< a nonblank line was read, so no header may follow
    std::uint64_t columns = 0;          ///< fields of the first data line; 0: none yet
    std::uint64_t first_data_line = 0;  ///< its line number
};
/// The lines of part `part` of `parts` of `text` (without the byte order mark at its start).
std::string_view text_part(std::string_view text, std::uint64_t part, std::uint64_t parts);
/// The same bytes read from a file: the part's share and the rest of its last line.
std::string read_text_part(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts);
text_part_summary summarize_text_part(std::string_view lines);
/// The context after the parts summed up in `parts`, in file order.
text_context context_after(std::span<const text_part_summary> parts);
/// The points of a part's lines read after `before`; throws frnn::error as
/// parse_text_points does, with line and point numbers in the whole file.
point_set parse_text_part(std::string_view lines, std::string_view name, const text_context& before);

/// The same parsers over bytes already in memory; `name` is the file name used in messages.
point_set parse_text_points(std::string_view text, std::string_view name);
point_set parse_ply_points(std::string_view bytes, std::string_view name);

/// The header of an .npy array: what the dictionary said and where the data starts.
struct npy_header {
    std::string descr;                 ///< e.g. "<f8"
    bool fortran_order = false;
    std::vector<std::uint64_t> shape;  ///< empty for a scalar
    std::size_t data_offset = 0;       ///< bytes from the magic to the first data byte
    std::uint64_t count() const;       ///< product of the shape (1 for a scalar)
};
/// Parses the magic, version and header dictionary at the start of `bytes`, which must hold
/// at least the whole header. Throws frnn::error naming `name` and the byte offset.
npy_header parse_npy_header(std::string_view bytes, std::string_view name);

}  // namespace frnn::io
