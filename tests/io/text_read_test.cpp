// The text point reader (.csv/.txt/.xyz): separators, comments, header, and bad lines.
#include "frnn/io/read.hpp"
#include "io/test_files.hpp"
#include "io/text_in_parts.hpp"

#include <random>

namespace frnn::test {
namespace {

std::vector<double> coords_of(const io::point_set& p) { return std::get<std::vector<double>>(p.coords); }

TEST(text_read, commas_with_header_and_comments) {
    const io::point_set p =
        io::parse_text_points("# made by hand\nx,y,z\n1,2,3\n\n  4.5 , -6e-1,+7 # trailing\n", "a.csv");
    EXPECT_EQ(p.dimension, 3);
    EXPECT_EQ(p.type(), io::precision::f64);
    EXPECT_EQ(coords_of(p), (std::vector<double>{1, 2, 3, 4.5, -0.6, 7}));
}

TEST(text_read, white_space_two_columns_crlf_and_bom) {
    const io::point_set p = io::parse_text_points("\xEF\xBB\xBF" "0.5\t1.5\r\n  2 3\r\n\r\n-1e3   4\r\n", "b.xyz");
    EXPECT_EQ(p.dimension, 2);
    EXPECT_EQ(coords_of(p), (std::vector<double>{0.5, 1.5, 2, 3, -1000, 4}));
}

TEST(text_read, no_final_newline) {
    EXPECT_EQ(coords_of(io::parse_text_points("1 2 3\n4 5 6", "c.txt")), (std::vector<double>{1, 2, 3, 4, 5, 6}));
}

TEST(text_read, values_parse_exactly) {
    const io::point_set p = io::parse_text_points("0.1,0.2,0.30000000000000004\n", "d.csv");
    EXPECT_EQ(coords_of(p), (std::vector<double>{0.1, 0.2, 0.30000000000000004}));
}

TEST(text_read, empty_inputs_give_zero_points) {
    for (const char* text : {"", "\n\n", "# only a comment\n", "x y z\n", "x,y\n# nothing\n"}) {
        const io::point_set p = io::parse_text_points(text, "e.csv");
        EXPECT_EQ(p.size(), 0u) << text;
    }
}

TEST(text_read, reads_files) {
    const auto dir = fresh_dir();
    const auto file = dir / "f.csv";
    write_bytes(file, "x,y\n1,2\n3,4\n");
    const io::point_set p = io::read_points(file);
    EXPECT_EQ(p.size(), 2u);
    EXPECT_EQ(p.dimension, 2);
}

void expect_bad(std::string_view text, std::initializer_list<std::string_view> parts) {
    expect_error([&] { io::parse_text_points(text, "pts.csv"); }, parts);
    expect_error([&] { io::parse_text_points(text, "pts.csv"); }, {"pts.csv: "});
}

TEST(text_read, one_column) { expect_bad("# c\n1\n2\n", {"line 2", "1 columns", "2 (x y) or 3 (x y z)"}); }
TEST(text_read, four_columns) { expect_bad("1,2,3,4\n", {"line 1", "4 columns"}); }
TEST(text_read, column_count_changes) { expect_bad("1 2 3\n4 5 6\n\n7 8\n", {"line 4", "2 columns, but line 1 has 3"}); }
TEST(text_read, bad_number_names_line_and_field) {
    expect_bad("x,y,z\n1,2,3\n4,5o,6\n", {"line 3", "field 2 '5o' is not a number"});
}
TEST(text_read, typo_in_first_line_is_not_a_header) { expect_bad("1.0,2.o,3\n4,5,6\n", {"line 1", "'2.o'"}); }
TEST(text_read, second_header_is_an_error) { expect_bad("x y\n1 2\nx y\n", {"line 3", "'x' is not a number"}); }
TEST(text_read, empty_field) { expect_bad("1,,3\n", {"line 1", "empty field 2"}); }
TEST(text_read, mixed_separators) { expect_bad("1 2,3\n", {"line 1", "'1 2'"}); }
TEST(text_read, out_of_range_number) { expect_bad("1 1e999 3\n", {"line 1", "'1e999'"}); }
TEST(text_read, nan_names_point_and_line) { expect_bad("1 2\n3 4\n# x\nnan 5\n", {"line 4", "point 2", "non-finite"}); }
TEST(text_read, infinity_names_point) { expect_bad("1,2,-inf\n", {"line 1", "point 0", "non-finite"}); }
TEST(text_read, missing_file) {
    expect_error([] { io::read_points("/nonexistent/frnn/p.csv"); }, {"/nonexistent/frnn/p.csv", "cannot open"});
}

// Read in parts (one per MPI rank): the points and the first error of the whole file.

/// A random text point file: data lines of 2 or 3 columns (commas or blanks, CRLF or not),
/// comments, blank lines, a header and a byte order mark now and then, and now and then one
/// line that the reader rejects somewhere.
std::string random_text(std::mt19937& rng) {
    auto chance = [&](double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; };
    auto pick = [&](int n) { return int(rng() % unsigned(n)); };
    const int columns = chance(0.5) ? 2 : 3;
    std::string text = chance(0.2) ? "\xEF\xBB\xBF" : "";
    for (int k = 0, n = pick(3); k < n; ++k) text += chance(0.5) ? "\n" : "# comment, 1 2 3\n";
    if (chance(0.5)) text += columns == 2 ? "x,y\n" : "x y z\n";
    const int lines = pick(40);
    const int bad_at = chance(0.5) ? pick(lines + 1) : -1;
    static const char* bad_lines[] = {"1,2o,3", "x y", "1 2 3 4", "1", "nan 1 2", "1,,2", "1 2,3", ""};
    for (int k = 0; k < lines; ++k) {
        const char* end = chance(0.2) ? "\r\n" : "\n";
        if (k == bad_at) {
            text += bad_lines[pick(7)];
            text += end;
            continue;
        }
        if (chance(0.1)) text += chance(0.5) ? std::string("  # note") + end : std::string(end);
        const int here = chance(0.03) ? 5 - columns : columns;  // a column count that changes
        const char* sep = chance(0.5) ? "," : " \t";
        for (int a = 0; a < here; ++a) text += (a ? sep : "") + std::to_string(pick(2000) - 1000) + "." + std::to_string(pick(100));
        text += chance(0.1) ? " # trailing" : "";
        text += end;
    }
    if (!text.empty() && chance(0.3)) text.pop_back();  // no final newline
    return text;
}

TEST(text_read, parts_give_the_points_and_the_first_error_of_the_whole) {
    std::mt19937 rng(5);
    int failing = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const std::string text = random_text(rng);
        const text_result whole = read_text_whole(text);
        failing += !whole.error.empty();
        for (std::uint64_t parts : {1, 2, 3, 5, 8, 13}) {
            std::string joined;
            for (std::uint64_t k = 0; k < parts; ++k) joined += io::text_part(text, k, parts);
            ASSERT_EQ(joined, text.substr(text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0)) << "parts " << parts;
            const text_result split = read_text_in_parts(text, parts);
            ASSERT_EQ(split.error, whole.error) << "parts " << parts << " of\n" << text;
            if (!whole.error.empty()) continue;
            ASSERT_EQ(split.coords, whole.coords) << "parts " << parts << " of\n" << text;
            ASSERT_EQ(split.dimension, whole.dimension) << "parts " << parts << " of\n" << text;
        }
    }
    // Both kinds of file were drawn.
    EXPECT_GT(failing, 50);
    EXPECT_LT(failing, 350);
}

TEST(text_read, files_parsed_on_threads_are_parsed_as_in_one) {
    const auto dir = fresh_dir();
    const auto file = dir / "big.csv";
    // Files of a few MiB, split at 1 MiB a part: random lines, a bad one at a random place
    // in some; the points or the first error are those of one serial parse.
    std::mt19937 rng(7);
    for (int trial = 0; trial < 6; ++trial) {
        std::string text = "x,y,z\n";
        while (text.size() < (std::size_t(3) << 20))
            text += std::to_string(rng() % 1000) + ",2.5,-" + std::to_string(rng() % 77) + "\n";
        // Trials 1, 3 and 5: a bad line in the first, second or third MiB.
        if (trial % 2 == 1) text.insert(text.find('\n', text.size() * std::size_t(trial) / 6) + 1, trial == 3 ? "1,2\n" : "1,nan,3\n");
        write_bytes(file, text);
        const text_result serial = read_text_whole(text);
        for (int threads : {1, 2, 3}) {
            text_result parallel;
            try {
                const io::point_set p = io::read_points(file, threads);
                parallel.coords = coords_of(p);
                parallel.dimension = p.dimension;
            } catch (const error& e) {
                parallel.error = std::string(e.what()).replace(0, file.string().size(), "p.csv");
            }
            ASSERT_EQ(parallel.error, serial.error) << threads << " threads";
            ASSERT_EQ(parallel.dimension, serial.dimension);
            ASSERT_TRUE(parallel.coords == serial.coords) << threads << " threads";
        }
    }
}

TEST(text_read, parts_read_from_a_file_are_its_parts) {
    const auto dir = fresh_dir();
    const auto file = dir / "p.xyz";
    std::mt19937 rng(6);
    std::vector<std::string> texts = {"", "\n", "1 2\n", "\xEF\xBB\xBF" "1 2\n3 4\n", "1 2\n3 4"};
    // A line longer than the reader's buffer, with part boundaries inside it.
    texts.push_back("1 2\n" + std::string(200000, ' ') + "3 4\n5 6\n");
    for (int k = 0; k < 20; ++k) texts.push_back(random_text(rng));
    for (const std::string& text : texts) {
        write_bytes(file, text);
        for (std::uint64_t parts : {1, 2, 3, 7, 40})
            for (std::uint64_t k = 0; k < parts; ++k)
                ASSERT_EQ(io::read_text_part(file, k, parts), io::text_part(text, k, parts)) << k << " of " << parts;
    }
    expect_error([&] { io::read_text_part(dir / "missing.csv", 0, 2); }, {"missing.csv", "cannot open"});
}

}  // namespace
}  // namespace frnn::test
