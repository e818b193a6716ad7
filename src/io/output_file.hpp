// output_file: a file written under a temporary name in the target's folder and renamed over
// the target by commit(); destroyed without commit (an exception on the way), it removes the
// temporary, so readers never see a partial file.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <vector>

namespace frnn::io::detail {

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

/// Collects values of type T and writes them to an output_file in large blocks.
template <class T>
class block_writer {
public:
    explicit block_writer(output_file& out) : out_(out) { block_.reserve(capacity); }
    void push(T value) {
        block_.push_back(value);
        if (block_.size() == capacity) flush();
    }
    void flush() {
        out_.write(block_.data(), block_.size() * sizeof(T));
        block_.clear();
    }

private:
    static constexpr std::size_t capacity = 1 << 14;
    output_file& out_;
    std::vector<T> block_;
};

}  // namespace frnn::io::detail
