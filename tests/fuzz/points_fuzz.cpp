// Fuzzing the point-file readers: any bytes, read as a text (.csv/.xyz), .ply or .npy file,
// give points or frnn::error, never a crash, a hang or memory beyond the file's size; the
// points read are finite and in a dimension of 2 or 3; a text file read in parts (one per MPI
// rank) and a binary .ply in slices of vertices give what the whole gives.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

#include "frnn/error.hpp"
#include "frnn/io/read.hpp"
#include "fuzz_input.hpp"
#include "io/text_in_parts.hpp"

namespace frnn::fuzz {
namespace {

void check(const io::point_set& p) {
    reached_checks();
    if (p.dimension != 2 && p.dimension != 3) fail("a reader gave a dimension other than 2 or 3");
    std::visit(
        [&](const auto& v) {
            if (v.size() % std::size_t(p.dimension) != 0) fail("a reader gave a partial point");
            for (auto x : v)
                if (!std::isfinite(x)) fail("a reader gave a non-finite coordinate");
        },
        p.coords);
}

/// The bytes in a file of this process's own, for the readers that take a path; the caller
/// removes it before anything is checked (a finding stops the process).
std::filesystem::path file_of(std::string_view bytes, const char* extension) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("frnn-fuzz-" + std::to_string(::getpid()) + extension);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return file;
}

void read_npy(std::string_view bytes) {
    const std::filesystem::path file = file_of(bytes, ".npy");
    std::vector<io::point_set> whole;
    std::vector<io::point_slice> slices;
    try {
        whole.push_back(io::read_npy_points(file));
    } catch (const error&) {
    }
    try {
        for (std::uint64_t part = 0; part < 3; ++part) slices.push_back(io::read_npy_slice(file, part, 3));
    } catch (const error&) {
    }
    try {
        io::read_npy_values(file);
    } catch (const error&) {
    }
    std::filesystem::remove(file);
    for (const auto& p : whole) check(p);
    for (std::uint64_t part = 0; part < slices.size(); ++part) {
        const io::point_slice& s = slices[part];
        check(s.points);
        if (s.first != io::slice_start(s.total, part, 3) || s.first + s.points.size() != io::slice_start(s.total, part + 1, 3))
            fail("an .npy slice holds other rows than its share");
    }
}

/// A .ply read in 3 slices of vertices, when it can be, gives the points or the first error
/// of the whole.
void read_ply_slices(std::string_view bytes) {
    const std::filesystem::path file = file_of(bytes, ".ply");
    std::string whole_error, slice_error;
    io::point_set whole;
    std::vector<io::point_slice> slices;
    bool sliced = false;
    try {
        whole = io::read_ply_points(file);
    } catch (const error& e) {
        whole_error = e.what();
    }
    try {
        for (std::uint64_t part = 0; part < 3; ++part)
            if (auto s = io::read_ply_slice(file, part, 3)) slices.push_back(std::move(*s)), sliced = true;
    } catch (const error& e) {
        slice_error = e.what();
        sliced = true;
    }
    std::filesystem::remove(file);
    if (!sliced) return;
    if (slice_error != whole_error) fail(("a .ply read in slices fails otherwise than whole: " + slice_error).c_str());
    if (!whole_error.empty()) return;
    if (slices.size() != 3) fail("a .ply was read in some slices only");
    std::size_t values = 0;
    for (const io::point_slice& s : slices) {
        check(s.points);
        if (s.points.dimension != whole.dimension || s.points.type() != whole.type()) fail("a .ply slice has another layout");
        values += s.points.size() * std::size_t(s.points.dimension);
        std::visit([&](const auto& part) {
            const auto& all = std::get<std::decay_t<decltype(part)>>(whole.coords);
            const std::size_t at = std::size_t(s.first) * std::size_t(whole.dimension);
            if (at + part.size() > all.size() || !std::equal(part.begin(), part.end(), all.begin() + std::ptrdiff_t(at)))
                fail("a .ply slice holds other points than the whole file's");
        }, s.points.coords);
    }
    if (values != whole.size() * std::size_t(whole.dimension)) fail("the .ply slices do not add up to the whole");
}

/// A text file read in parts, as the ranks of a distributed query read it, gives the points or
/// the first error of the whole.
void read_text_in_parts(std::string_view bytes) {
    const test::text_result whole = test::read_text_whole(bytes);
    for (std::uint64_t parts : {2, 3, 7}) {
        const test::text_result split = test::read_text_in_parts(bytes, parts);
        if (split.error != whole.error || split.coords != whole.coords || split.dimension != whole.dimension)
            fail(("a text file read in " + std::to_string(parts) + " parts differs from the whole: " + split.error).c_str());
    }
}

}  // namespace
}  // namespace frnn::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    frnn::fuzz::fuzz_input in(data, size);
    const std::size_t format = in.below(3);
    const std::string_view bytes = in.rest();
    try {
        if (format == 0) frnn::fuzz::check(frnn::io::parse_text_points(bytes, "fuzz.csv"));
        else if (format == 1) frnn::fuzz::check(frnn::io::parse_ply_points(bytes, "fuzz.ply"));
    } catch (const frnn::error&) {
    }
    if (format == 0) frnn::fuzz::read_text_in_parts(bytes);
    if (format == 1) frnn::fuzz::read_ply_slices(bytes);
    if (format == 2) frnn::fuzz::read_npy(bytes);
    return 0;
}
