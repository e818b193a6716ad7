// Whole-file writes that never leave half a file: the content goes to a temporary name in the
// same directory, is flushed and closed, then renamed over the target (atomic on POSIX).
// O(size of the content). Thread-safe for distinct paths.
#pragma once
#include <string>
#include <string_view>

namespace frnn::bench {

/// A temporary path beside `path` (same directory, so the final rename is atomic).
std::string temporary_path_for(const std::string& path);

/// Writes `content` to `path` atomically; throws frnn::error saying which file failed and why.
void write_file_atomically(const std::string& path, std::string_view content);

/// Renames `from` over `to`; on failure removes `from` and throws frnn::error.
void commit_file(const std::string& from, const std::string& to);

}  // namespace frnn::bench
