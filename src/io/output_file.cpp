#include "output_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "util.hpp"

namespace frnn::io::detail {

namespace {
std::atomic<unsigned> temp_counter{0};
}

output_file::output_file(std::filesystem::path target) : target_(std::move(target)) {
    // A hidden name in the same folder, so that the final rename never crosses file systems.
    temp_ = target_;
    std::string name = ".";
    name += target_.filename().string();
    name += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(temp_counter++);
    temp_.replace_filename(name);
    file_ = std::fopen(temp_.string().c_str(), "wbx");
    if (!file_)
        fail(target_.string(), "cannot create temporary file " + temp_.string() + ": " +
                                   std::strerror(errno));
    buffer_.resize(1 << 20);
    std::setvbuf(file_, buffer_.data(), _IOFBF, buffer_.size());
}

output_file::~output_file() {
    if (file_) {
        std::fclose(file_);
        std::error_code ignored;
        std::filesystem::remove(temp_, ignored);
    }
}

void output_file::failed(const char* what) {
    const int code = errno;
    std::fclose(file_);
    file_ = nullptr;
    std::error_code ignored;
    std::filesystem::remove(temp_, ignored);
    fail(target_.string(), std::string(what) + ": " + std::strerror(code));
}

void output_file::write(const void* data, std::size_t bytes) {
    if (!file_) fail(target_.string(), "write after the file was closed");
    if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) failed("write failed");
    written_ += bytes;
}

void output_file::patch(std::uint64_t offset, const void* data, std::size_t bytes) {
    if (!file_) fail(target_.string(), "write after the file was closed");
    if (std::fseek(file_, long(offset), SEEK_SET) != 0 ||
        std::fwrite(data, 1, bytes, file_) != bytes || std::fseek(file_, 0, SEEK_END) != 0)
        failed("write failed");
}

void output_file::commit() {
    if (!file_) fail(target_.string(), "commit after the file was closed");
    if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) failed("write failed");
    if (std::fclose(file_) != 0) {
        file_ = nullptr;
        std::error_code ignored;
        std::filesystem::remove(temp_, ignored);
        fail(target_.string(), std::string("write failed: ") + std::strerror(errno));
    }
    file_ = nullptr;
    std::error_code ec;
    std::filesystem::rename(temp_, target_, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(temp_, ignored);
        fail(target_.string(), "cannot rename the temporary file over it: " + ec.message());
    }
}

}  // namespace frnn::io::detail
