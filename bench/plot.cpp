// The PNG plot of report.hpp, drawn by gnuplot (Debian gnuplot-nox) in a child process.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <map>
#include <tuple>

#include "frnn/bench/report.hpp"
#include "frnn/error.hpp"
#include "frnn/io/gnuplot.hpp"

namespace frnn::bench {
namespace {

// One colour and point shape per method, one dash pattern per thread count, in every panel.
std::string style(const std::string& method, int threads) {
    static const std::map<std::string, std::pair<const char*, int>> look{
        {"frnn", {"#c0392b", 7}}, {"nanoflann", {"#2471a3", 5}},
        {"cell-list", {"#229954", 9}}, {"brute", {"#7d3c98", 13}}};
    const auto it = look.find(method);
    const auto [colour, point] = it != look.end() ? it->second : std::pair{"#555555", 1};
    return std::string("lc rgb '") + colour + "' pt " + std::to_string(point) + " dt " +
           std::to_string(std::min(threads, 5));
}

// The gnuplot script: one data block per (workload, method, threads) series, one panel per
// workload, log-log axes; the image size for that many panels.
std::string plot_script(const report& rep, int& width, int& height) {
    // workload -> (method order, threads) -> (N, ns/particle) points
    using series_key = std::tuple<std::size_t, int, std::string>;
    std::map<std::string, std::map<series_key, std::map<std::size_t, double>>> panels;
    for (const auto& r : rep.rows)
        if (r.phase == "build+list") {
            const auto order = std::size_t(std::find(methods.begin(), methods.end(), r.method) -
                                           methods.begin());
            panels[r.workload][{order, r.threads, r.method}][r.n] = r.ns_per_particle;
        }
    const std::size_t count = panels.size();
    const std::size_t cols = count > 1 ? 2 : 1, rows = (count + cols - 1) / cols;
    width = int(720 * cols);
    height = int(460 * rows);

    std::string s;
    s += "set logscale xy\nset grid\nset key outside right top\n";
    s += "set xlabel 'N (points)'\nset ylabel 'ns per particle (build + lists)'\n";
    int block = 0;
    std::string plots;
    for (const auto& [workload, series] : panels) {
        std::string panel = "set title " + io::gnuplot_quoted(workload + ": build + full neighbor lists") + "\n";
        // One size only: give the log axis a range around it (gnuplot refuses an empty one).
        std::size_t lo = SIZE_MAX, hi = 0;
        for (const auto& entry : series)
            for (const auto& point : entry.second) lo = std::min(lo, point.first), hi = std::max(hi, point.first);
        panel += lo == hi ? "set xrange [" + std::to_string(lo / 2) + ":" + std::to_string(hi * 2) + "]\n"
                          : std::string("set autoscale x\n");
        std::string items;
        for (const auto& [key, points] : series) {
            const auto& [order, threads, method] = key;
            const std::string label = method + " " + std::to_string(threads) + "t";
            const std::string name = "$s" + std::to_string(block++);
            s += io::gnuplot_data_block(name, {points.begin(), points.end()});
            items += std::string(items.empty() ? "plot " : ", ") + name +
                     " using 1:2 with linespoints lw 2 " + style(method, threads) +
                     " title " + io::gnuplot_quoted(label);
        }
        plots += panel + items + "\n";
    }
    s += "set multiplot layout " + std::to_string(rows) + "," + std::to_string(cols) + "\n";
    s += plots;
    s += "unset multiplot\n";
    return s;
}

}  // namespace

bool write_plot(const report& rep, const std::string& png_path, std::string& why) {
    bool any = false;
    for (const auto& r : rep.rows) any = any || r.phase == "build+list";
    if (!any) throw error("plot: no build+list measurements to plot");
    int width = 0, height = 0;
    const std::string commands = plot_script(rep, width, height);
    return io::draw_with_gnuplot(commands, width, height, png_path, why);
}

}  // namespace frnn::bench
