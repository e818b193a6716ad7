// The PNG plot of report.hpp, drawn by gnuplot (Debian gnuplot-nox) in a child process.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <map>
#include <tuple>

#include "frnn/io/atomic_file.hpp"
#include "frnn/bench/report.hpp"
#include "frnn/error.hpp"

extern char** environ;

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

// gnuplot single-quoted string: a quote is written twice.
std::string quoted(const std::string& text) {
    std::string out = "'";
    for (char ch : text) out += ch == '\'' ? std::string("''") : std::string(1, ch);
    return out + "'";
}

// Runs `gnuplot script`; returns its exit status, or -1 (errno ENOENT) when it is not installed.
int run_gnuplot(const std::string& script) {
    const char* argv[] = {"gnuplot", script.c_str(), nullptr};
    pid_t pid = 0;
    const int err = posix_spawnp(&pid, "gnuplot", nullptr, nullptr, const_cast<char**>(argv), environ);
    if (err != 0) {
        errno = err;
        return -1;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw error("plot: waiting for gnuplot failed: " + std::string(std::strerror(errno)));
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// The gnuplot script: one data block per (workload, method, threads) series, one panel per
// workload, log-log axes.
std::string plot_script(const report& rep, const std::string& png) {
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

    std::string s = "set terminal pngcairo size " + std::to_string(720 * cols) + "," +
                    std::to_string(460 * rows) + " font ',10'\n";
    s += "set output " + quoted(png) + "\n";
    s += "set logscale xy\nset grid\nset key outside right top\n";
    s += "set xlabel 'N (points)'\nset ylabel 'ns per particle (build + lists)'\n";
    int block = 0;
    std::string plots;
    for (const auto& [workload, series] : panels) {
        std::string panel = "set title " + quoted(workload + ": build + full neighbor lists") + "\n";
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
            s += name + " << EOD\n";
            for (const auto& [n, ns] : points) {
                char line[96];
                std::snprintf(line, sizeof line, "%zu %.6g\n", n, ns);
                s += line;
            }
            s += "EOD\n";
            items += std::string(items.empty() ? "plot " : ", ") + name +
                     " using 1:2 with linespoints lw 2 " + style(method, threads) +
                     " title " + quoted(label);
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
    const std::string temp_png = io::temporary_path_beside(png_path).string() + ".png";
    const std::string script_path = io::temporary_path_beside(png_path).string() + ".gp";
    io::write_file_atomically(script_path, plot_script(rep, temp_png));
    const int status = run_gnuplot(script_path);
    const int spawn_errno = errno;
    std::remove(script_path.c_str());
    if (status == -1) {
        why = "gnuplot not found (" + std::string(std::strerror(spawn_errno)) +
              "): install Debian's gnuplot-nox to get " + png_path;
        return false;
    }
    if (status != 0) {
        std::remove(temp_png.c_str());
        throw error("plot: gnuplot exited with status " + std::to_string(status) + " writing " +
                    png_path);
    }
    io::commit_temporary(temp_png, png_path);
    return true;
}

}  // namespace frnn::bench
