// `frnn query --cell ... [--pbc ...]`: pairs of atoms in a periodic cell of any shape
// (frnn::lattice_grid), each pair of atoms once per periodic image, with its shift S.
// Outputs: .npy int64 (M, 2 + dim) rows i, j, S; .csv "i,j,S_a,S_b[,S_c],distance".
#ifdef FRNN_IO_AVAILABLE  // the tool reads and writes point files only with frnn_io
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "frnn/io/atomic_file.hpp"
#include "frnn/io/write.hpp"
#include "frnn/lattice.hpp"
#include "query_args.hpp"

namespace frnn::app {

namespace {

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> items;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        items.push_back(text.substr(start, comma - start));
        if (comma == std::string::npos) return items;
        start = comma + 1;
    }
}

template <int D>
lattice<D> parse_cell(const query_args& a) {
    const auto items = split(a.cell);
    if (items.size() != std::size_t(D * D))
        throw CLI::ValidationError("--cell", "needs " + std::to_string(D * D) + " numbers for " + std::to_string(D) +
                                                 "-D points (the lattice vectors as rows: ax,ay" +
                                                 (D == 3 ? ",az,bx,...,cz" : ",bx,by") + "); got " +
                                                 std::to_string(items.size()));
    lattice<D> cell;
    for (std::size_t k = 0; k < items.size(); ++k) {
        double v = 0;
        const auto& item = items[k];
        const auto r = std::from_chars(item.data(), item.data() + item.size(), v);
        if (item.empty() || r.ec != std::errc() || r.ptr != item.data() + item.size())
            throw CLI::ValidationError("--cell", "'" + item + "' (number " + std::to_string(k + 1) + ") is not a number");
        cell.vectors[k / D][k % D] = v;
    }
    cell.pbc.fill(true);
    if (!a.pbc.empty()) {
        const auto flags = split(a.pbc);
        if (flags.size() != std::size_t(D))
            throw CLI::ValidationError("--pbc", "needs " + std::to_string(D) + " flags (1 or 0 per lattice vector); got " +
                                                    std::to_string(flags.size()));
        for (int k = 0; k < D; ++k) {
            const auto& f = flags[std::size_t(k)];
            if (f != "0" && f != "1" && f != "true" && f != "false")
                throw CLI::ValidationError("--pbc", "'" + f + "' is not 1, 0, true or false");
            cell.pbc[std::size_t(k)] = f == "1" || f == "true";
        }
    }
    return cell;
}

/// Each pair of atoms once per image (the half lists), as .npy rows or .csv lines.
template <class T, int D>
void write_pairs(const std::string& file, const lattice_csr<T, D>& lists) {
    const std::size_t m = lists.size();
    if (lower_extension(file) == ".npy") {
        std::vector<std::int64_t> rows(m * (2 + D));
        for (std::size_t i = 0; i < lists.rows(); ++i)
            for (std::uint64_t e = lists.offsets[i]; e < lists.offsets[i + 1]; ++e) {
                std::int64_t* row = rows.data() + e * (2 + D);
                row[0] = std::int64_t(i);
                row[1] = lists.indices[e];
                for (int k = 0; k < D; ++k) row[2 + k] = lists.shifts[e * D + k];
            }
        const std::uint64_t shape[2] = {m, 2 + D};
        io::write_npy<std::int64_t>(file, rows, shape);
        return;
    }
    io::output_file out(file);
    out.write(D == 3 ? "i,j,S_a,S_b,S_c,distance\n" : "i,j,S_a,S_b,distance\n");
    std::string text;
    char number[40];
    for (std::size_t i = 0; i < lists.rows(); ++i) {
        for (std::uint64_t e = lists.offsets[i]; e < lists.offsets[i + 1]; ++e) {
            text += std::to_string(i) + ',' + std::to_string(lists.indices[e]);
            for (int k = 0; k < D; ++k) text += ',' + std::to_string(lists.shifts[e * D + k]);
            const auto r = std::to_chars(number, number + sizeof number, lists.distances[e]);  // shortest round trip
            text += ',' + std::string(number, r.ptr) + '\n';
        }
        if (text.size() > (1 << 20)) out.write(text), text.clear();
    }
    out.write(text);
    out.commit();
}

}  // namespace

void check_lattice_usage(const query_args& a) {
    if (a.cell.empty()) {
        if (!a.pbc.empty()) throw CLI::ValidationError("--pbc", "needs --cell");
        return;
    }
    auto refuse = [](const char* option, bool given) {
        if (given) throw CLI::ValidationError(option, "does not apply with --cell");
    };
    refuse("--periodic", !a.periodic.empty());
    refuse("--queries", !a.queries.empty());
    refuse("--knn", a.knn != 0);
    refuse("--cell-size", a.cell_size != 0);
    refuse("--radius", !a.radius_file.empty());
    refuse("--backend", a.backend != "cpu");
    if (!a.output.empty() && lower_extension(a.output) != ".npy" && lower_extension(a.output) != ".csv")
        throw CLI::ValidationError("--output", "'" + a.output + "': with --cell, .npy (rows i, j, S) or .csv");
}

void run_lattice_query(const query_args& a, const io::point_set& data, double read_ms) {
    stopwatch clock;
    io::visit_points(data, [&]<class T, int D>(std::span<const T> xyz) {
        const lattice<D> cell = parse_cell<D>(a);
        lattice_options options;
        options.threads = a.threads;
        lattice_grid<T, D> g(xyz, cell, T(a.radius), options);
        const double build_ms = clock.lap_ms();
        lattice_list_options lo;
        lo.half = true;
        lo.self = a.self;
        lo.distances = true;
        lo.order = row_order::index;
        const auto lists = g.neighbor_lists(lo);
        const double query_ms = clock.lap_ms();
        if (!a.output.empty()) write_pairs<T, D>(a.output, lists);
        const double write_ms = clock.lap_ms();
        std::string pbc;
        for (int k = 0; k < D; ++k) pbc += (k ? "," : "") + std::string(cell.pbc[std::size_t(k)] ? "1" : "0");
        const std::string input = a.input.empty() ? a.generate : a.input;
        if (a.json) {
            nlohmann::ordered_json j;
            j["input"] = input;
            j["points"] = g.size();
            j["dimension"] = D;
            j["precision"] = io::to_string(data.type());
            j["cutoff"] = a.radius;
            j["cell"] = cell.vectors;
            j["pbc"] = cell.pbc;
            j["self"] = a.self;
            j["pairs"] = lists.size();
            j["images"] = g.image_count();
            j["output"] = a.output.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(a.output);
            j["time_ms"] = {{"read", read_ms}, {"build", build_ms}, {"query", query_ms}, {"write", write_ms}};
            std::cout << j.dump(2) << '\n';
            return;
        }
        std::printf("points     %zu (%dD, %s) from %s\n", g.size(), D, std::string(io::to_string(data.type())).c_str(),
                    input.c_str());
        std::printf("cell       periodic %s, %zu image copies searched\n", pbc.c_str(), g.image_count());
        std::printf("cutoff     %g%s\n", a.radius, a.self ? ", self pairs included" : "");
        std::printf("pairs      %zu (each pair of atoms once per image)\n", lists.size());
        std::printf("time       read %.1f ms, build %.1f ms, query %.1f ms, write %.1f ms\n", read_ms, build_ms,
                    query_ms, write_ms);
        if (!a.output.empty()) std::printf("output     %s\n", a.output.c_str());
    });
}

}  // namespace frnn::app
#endif
