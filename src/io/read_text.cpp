// Text point reader (.csv, .txt, .xyz): one point per line, 2 or 3 numbers separated by commas
// or by white space. '#' starts a comment; blank lines are skipped; one header line is allowed
// before the data when none of its fields is a number (so a typo in the first data line is
// reported, not mistaken for a header). The file may also be read in parts, one per MPI rank
// (frnn/io/read.hpp), with the points and the first error of the whole.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "frnn/io/read.hpp"
#include "frnn/parallel.hpp"
#include "util.hpp"

namespace frnn::io {

namespace {
constexpr std::string_view blanks = " \t\r\v\f";

std::string_view trim(std::string_view s) {
    const std::size_t b = s.find_first_not_of(blanks);
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(blanks) - b + 1);
}

// Fields of one line: split at commas when the line has one, else at white space.
void split_fields(std::string_view line, std::vector<std::string_view>& fields) {
    fields.clear();
    if (line.find(',') != std::string_view::npos) {
        std::size_t start = 0;
        while (true) {
            const std::size_t comma = line.find(',', start);
            fields.push_back(trim(line.substr(start, comma - start)));
            if (comma == std::string_view::npos) break;
            start = comma + 1;
        }
        return;
    }
    std::size_t pos = 0;
    while ((pos = line.find_first_not_of(blanks, pos)) != std::string_view::npos) {
        const std::size_t end = line.find_first_of(blanks, pos);
        fields.push_back(line.substr(pos, end - pos));
        pos = end;
    }
}

// Calls f(number, line) for each line of `text`, numbered from 1, without its comment and the
// blanks around it.
template <class F>
void for_each_line(std::string_view text, F&& f) {
    std::uint64_t number = 0;
    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t eol = text.find('\n', pos);
        if (eol == std::string_view::npos) eol = text.size();
        const std::string_view line = text.substr(pos, eol - pos);
        pos = eol + 1;
        f(++number, trim(line.substr(0, line.find('#'))));
    }
}

std::string_view without_byte_order_mark(std::string_view text) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    return text;
}

// The first byte of the first line that starts at or after byte b.
std::size_t line_start_at_or_after(std::string_view text, std::size_t b) {
    if (b == 0) return 0;
    const std::size_t newline = text.find('\n', b - 1);
    return newline == std::string_view::npos ? text.size() : newline + 1;
}
}  // namespace

point_set parse_text_part(std::string_view text, std::string_view name, const text_context& before) {
    std::vector<double> coords;
    std::vector<std::string_view> fields;
    std::uint64_t columns = before.columns, first_data_line = before.first_data_line, line_number = 0;
    // A header is the file's first nonblank line, and only when none of its fields is a number
    // (so a typo in the first data line is reported, not mistaken for a header).
    bool header_allowed = !before.any_nonblank;
    auto where = [&] { return "line " + std::to_string(line_number) + ": "; };

    for_each_line(text, [&](std::uint64_t number, std::string_view line) {
        line_number = before.lines + number;
        if (line.empty()) return;
        split_fields(line, fields);
        double values[3];
        std::size_t numeric = 0, bad = fields.size();
        for (std::size_t k = 0; k < fields.size(); ++k) {
            double v;
            if (detail::parse_number(fields[k], v)) {
                if (numeric < 3) values[numeric] = v;
                ++numeric;
            } else if (bad == fields.size()) {
                bad = k;
            }
        }
        const bool header = header_allowed && numeric == 0;
        header_allowed = false;
        if (header) return;  // e.g. "x,y,z"
        if (bad != fields.size())
            detail::fail(name, where() + (fields[bad].empty()
                                              ? "empty field " + std::to_string(bad + 1)
                                              : "field " + std::to_string(bad + 1) + " '" +
                                                    std::string(fields[bad]) + "' is not a number"));
        if (columns == 0) {
            if (fields.size() != 2 && fields.size() != 3)
                detail::fail(name, where() + std::to_string(fields.size()) +
                                       " columns: point files need 2 (x y) or 3 (x y z)");
            columns = fields.size();
            first_data_line = line_number;
        } else if (fields.size() != columns) {
            detail::fail(name, where() + std::to_string(fields.size()) + " columns, but line " +
                                   std::to_string(first_data_line) + " has " +
                                   std::to_string(columns));
        }
        for (std::size_t a = 0; a < columns; ++a) {
            if (!std::isfinite(values[a]))
                detail::fail(name, where() + "point " + std::to_string(before.points + coords.size() / columns) +
                                       " has a non-finite coordinate (" +
                                       std::string(fields[a]) + ")");
            coords.push_back(values[a]);
        }
    });
    point_set points;
    points.dimension = columns == 0 ? 3 : int(columns);
    points.coords = std::move(coords);
    return points;
}

point_set parse_text_points(std::string_view text, std::string_view name) {
    return parse_text_part(without_byte_order_mark(text), name, {});
}

text_part_summary summarize_text_part(std::string_view lines) {
    text_part_summary s;
    std::vector<std::string_view> fields;
    for_each_line(lines, [&](std::uint64_t number, std::string_view line) {
        s.lines = number;
        if (line.empty() || ++s.nonblank > 2) return;
        split_fields(line, fields);
        if (s.nonblank == 2) {
            s.second_line = number;
            s.second_fields = fields.size();
            return;
        }
        s.first_line = number;
        s.first_fields = fields.size();
        double v;
        s.first_is_header = std::none_of(fields.begin(), fields.end(), [&](std::string_view f) { return detail::parse_number(f, v); });
    });
    return s;
}

text_context context_after(std::span<const text_part_summary> parts) {
    text_context c;
    for (const text_part_summary& s : parts) {
        if (s.nonblank > 0) {
            const bool header = !c.any_nonblank && s.first_is_header;
            if (c.columns == 0 && !header) {
                c.columns = s.first_fields;
                c.first_data_line = c.lines + s.first_line;
            } else if (c.columns == 0 && s.nonblank > 1) {
                c.columns = s.second_fields;
                c.first_data_line = c.lines + s.second_line;
            }
            c.points += s.nonblank - (header ? 1 : 0);
            c.any_nonblank = true;
        }
        c.lines += s.lines;
    }
    return c;
}

std::string_view text_part(std::string_view text, std::uint64_t part, std::uint64_t parts) {
    const std::size_t b = line_start_at_or_after(text, slice_start(text.size(), part, parts));
    const std::size_t e = line_start_at_or_after(text, slice_start(text.size(), part + 1, parts));
    const std::string_view lines = text.substr(b, e - b);
    return b == 0 ? without_byte_order_mark(lines) : lines;
}

std::string read_text_part(const std::filesystem::path& file, std::uint64_t part, std::uint64_t parts) {
    const std::string name = file.string();
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(name.c_str(), "rb"), std::fclose);
    if (!f) detail::fail(name, std::string("cannot open: ") + std::strerror(errno));
    auto seek = [&](std::uint64_t offset) {
        if (::fseeko(f.get(), off_t(offset), SEEK_SET) != 0) detail::fail(name, std::string("cannot seek: ") + std::strerror(errno));
    };
    if (::fseeko(f.get(), 0, SEEK_END) != 0) detail::fail(name, std::string("cannot seek: ") + std::strerror(errno));
    const std::uint64_t size = std::uint64_t(::ftello(f.get()));
    // As line_start_at_or_after, reading from byte b - 1 until a newline.
    auto line_start = [&](std::uint64_t b) {
        if (b == 0) return std::uint64_t(0);
        seek(b - 1);
        char buffer[1 << 16];
        for (std::uint64_t at = b - 1;;) {
            const std::size_t n = std::fread(buffer, 1, sizeof buffer, f.get());
            if (const void* newline = std::memchr(buffer, '\n', n)) return at + std::uint64_t(static_cast<const char*>(newline) - buffer) + 1;
            if (n < sizeof buffer) return size;
            at += n;
        }
    };
    const std::uint64_t b = line_start(slice_start(size, part, parts)), e = line_start(slice_start(size, part + 1, parts));
    if (std::ferror(f.get())) detail::fail(name, std::string("read error: ") + std::strerror(errno));
    std::string lines(e - b, '\0');
    seek(b);
    if (std::fread(lines.data(), 1, lines.size(), f.get()) != lines.size())
        detail::fail(name, "read error: the file changed or ended while being read");
    if (b == 0 && without_byte_order_mark(lines).size() != lines.size()) lines.erase(0, 3);
    return lines;
}

point_set read_text_points(const std::filesystem::path& file, int threads) {
    const std::string bytes = detail::read_file(file);
    const std::string_view text = bytes;
    const std::string name = file.string();
    // A part of at least 1 MiB per thread: smaller files are parsed in one.
    const std::size_t parts = std::clamp<std::size_t>(text.size() >> 20, 1, std::size_t(resolve_thread_count(threads)));
    if (parts == 1) return parse_text_points(text, name);
    std::vector<text_part_summary> summaries(parts);
    parallel_chunks(parts, threads, [&](std::size_t k, int) { summaries[k] = summarize_text_part(text_part(text, k, parts)); });
    std::vector<point_set> read(parts);
    std::vector<std::string> errors(parts);
    parallel_chunks(parts, threads, [&](std::size_t k, int) {
        try {
            read[k] = parse_text_part(text_part(text, k, parts), name, context_after(std::span(summaries).first(k)));
        } catch (const error& e) {
            errors[k] = e.what();
        }
    });
    for (const std::string& e : errors)  // the first part's error is the file's first
        if (!e.empty()) throw error(e);
    const text_context all = context_after(summaries);
    std::vector<double> coords;
    coords.reserve(std::size_t(all.points * all.columns));
    for (const point_set& p : read) {
        const auto& part = std::get<std::vector<double>>(p.coords);
        coords.insert(coords.end(), part.begin(), part.end());
    }
    point_set points;
    points.dimension = all.columns == 0 ? 3 : int(all.columns);
    points.coords = std::move(coords);
    return points;
}

}  // namespace frnn::io
