// The atomic file writer of frnn/io/atomic_file.hpp.
#include "frnn/io/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "util.hpp"

namespace frnn::io {

namespace {
std::atomic<unsigned> temp_counter{0};

void remove_quietly(const std::filesystem::path& p) {
    std::error_code ignored;
    std::filesystem::remove(p, ignored);
}
}  // namespace

std::filesystem::path temporary_path_beside(const std::filesystem::path& path) {
    // Appended piece by piece: GCC 12 warns (-Wrestrict, wrongly) on "text" + std::string.
    std::string name = ".";
    name += path.filename().string();
    name += ".tmp-";
    name += std::to_string(::getpid());
    name += '-';
    name += std::to_string(temp_counter++);
    std::filesystem::path temp = path;
    temp.replace_filename(name);
    return temp;
}

void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        remove_quietly(temporary);
        detail::fail(path.string(), "cannot rename the temporary file over it: " + ec.message());
    }
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
    if (path.empty()) detail::fail("(no name)", "cannot write a file with an empty name");
    output_file out(path);
    out.write(content);
    out.commit();
}

output_file::output_file(std::filesystem::path target)
    : target_(std::move(target)), temp_(temporary_path_beside(target_)) {
    file_ = std::fopen(temp_.string().c_str(), "wbx");
    if (!file_)
        detail::fail(target_.string(), "cannot create temporary file " + temp_.string() + ": " + std::strerror(errno));
    buffer_.resize(1 << 20);
    std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
}

output_file::~output_file() {
    if (file_) {
        std::fclose(file_);
        remove_quietly(temp_);
    }
}

void output_file::failed(const char* what) {
    const int code = errno;
    std::fclose(file_);
    file_ = nullptr;
    remove_quietly(temp_);
    detail::fail(target_.string(), std::string(what) + ": " + std::strerror(code));
}

void output_file::write(const void* data, std::size_t bytes) {
    if (!file_) detail::fail(target_.string(), "write after the file was closed");
    if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) failed("write failed");
    written_ += bytes;
}

void output_file::patch(std::uint64_t offset, const void* data, std::size_t bytes) {
    if (!file_) detail::fail(target_.string(), "write after the file was closed");
    if (std::fseek(file_, long(offset), SEEK_SET) != 0 || std::fwrite(data, 1, bytes, file_) != bytes ||
        std::fseek(file_, 0, SEEK_END) != 0)
        failed("write failed");
}

void output_file::commit() {
    if (!file_) detail::fail(target_.string(), "commit after the file was closed");
    if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) failed("write failed");
    if (std::fclose(file_) != 0) {
        file_ = nullptr;
        remove_quietly(temp_);
        detail::fail(target_.string(), std::string("write failed: ") + std::strerror(errno));
    }
    file_ = nullptr;
    commit_temporary(temp_, target_);
}

}  // namespace frnn::io
