// Files that readers never see half written: the content goes to a hidden temporary name in the
// target's folder (so the final rename never crosses file systems), is flushed and synced, then
// renamed over the target (atomic on POSIX). A write abandoned on the way (an exception) removes
// its temporary. The one such writer of frnn's tool, simulation, benchmarks and viewer.
// Errors throw frnn::error "<target>: <what went wrong>".
// Thread safety: distinct objects and distinct targets may be used from any threads.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <vector>

namespace frnn::io {

/// Writes `content` to `path` atomically (through an output_file).
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// For a file another program writes (gnuplot's PNG): a hidden temporary name beside `path`,
/// unique in this process, and the rename of that file over `path` (removed when it fails).
std::filesystem::path temporary_path_beside(const std::filesystem::path& path);
void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path);

/// A file written under a temporary name and renamed over the target by commit(); destroyed
/// without commit, it removes the temporary.
class output_file {
public:
    explicit output_file(std::filesystem::path target);
    ~output_file();
    output_file(const output_file&) = delete;
    output_file& operator=(const output_file&) = delete;

    void write(const void* data, std::size_t bytes);
    void write(std::string_view text) { write(text.data(), text.size()); }
    /// Bytes written so far.
    std::uint64_t position() const { return written_; }
    /// Replaces bytes written earlier at `offset` (e.g. a checksum known only at the end).
    void patch(std::uint64_t offset, const void* data, std::size_t bytes);
    /// Flushes, syncs and renames the temporary file over the target.
    void commit();

private:
    [[noreturn]] void failed(const char* what);
    std::filesystem::path target_, temp_;
    std::FILE* file_ = nullptr;
    std::uint64_t written_ = 0;
    std::vector<char> buffer_;
};

}  // namespace frnn::io
