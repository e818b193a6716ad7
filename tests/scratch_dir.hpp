// A test's scratch folder: created empty under the temporary directory ($TMPDIR, which
// scripts/test points at a folder it checks for leftovers) and removed with its contents when
// the guard goes out of scope, so a failed assertion leaves nothing behind either.
#pragma once
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace frnn::test {

class scratch_dir {
public:
    /// <temp>/frnn_<pid>_<name>, emptied first (a crashed earlier run with the same pid).
    explicit scratch_dir(const std::string& name)
        : path_(std::filesystem::temp_directory_path() / ("frnn_" + std::to_string(::getpid()) + "_" + name)) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~scratch_dir() {
        std::error_code ignored;  // a destructor must not throw; scripts/test reports leftovers
        std::filesystem::remove_all(path_, ignored);
    }
    scratch_dir(const scratch_dir&) = delete;
    scratch_dir& operator=(const scratch_dir&) = delete;

    const std::filesystem::path& path() const& { return path_; }
    operator const std::filesystem::path&() const& { return path_; }
    std::filesystem::path operator/(const std::filesystem::path& name) const& { return path_ / name; }
    std::string string() const& { return path_.string(); }
    // On a temporary guard the folder would be gone before the path is used.
    const std::filesystem::path& path() const&& = delete;
    operator const std::filesystem::path&() const&& = delete;
    std::filesystem::path operator/(const std::filesystem::path&) const&& = delete;
    std::string string() const&& = delete;

private:
    std::filesystem::path path_;
};

}  // namespace frnn::test
