// Text point reader (.csv, .txt, .xyz): one point per line, 2 or 3 numbers separated by commas
// or by white space. '#' starts a comment; blank lines are skipped; one header line is allowed
// before the data when none of its fields is a number (so a typo in the first data line is
// reported, not mistaken for a header).
#include <vector>

#include "frnn/io/read.hpp"
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
}  // namespace

point_set parse_text_points(std::string_view text, std::string_view name) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark
    std::vector<double> coords;
    std::vector<std::string_view> fields;
    std::size_t columns = 0, first_data_line = 0, line_number = 0;
    bool header_seen = false;
    auto where = [&] { return "line " + std::to_string(line_number) + ": "; };

    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t eol = text.find('\n', pos);
        if (eol == std::string_view::npos) eol = text.size();
        std::string_view line = text.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_number;
        line = trim(line.substr(0, line.find('#')));
        if (line.empty()) continue;
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
        if (numeric == 0 && columns == 0 && !header_seen) {
            header_seen = true;  // e.g. "x,y,z"
            continue;
        }
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
                detail::fail(name, where() + "point " + std::to_string(coords.size() / columns) +
                                       " has a non-finite coordinate (" +
                                       std::string(fields[a]) + ")");
            coords.push_back(values[a]);
        }
    }
    point_set points;
    points.dimension = columns == 0 ? 3 : int(columns);
    points.coords = std::move(coords);
    return points;
}

point_set read_text_points(const std::filesystem::path& file) {
    return parse_text_points(detail::read_file(file), file.string());
}

}  // namespace frnn::io
