// gnuplot plots (frnn/io/gnuplot.hpp): the script and the image beside the target under
// temporary names; the script is removed, the image renamed into place.
#include "frnn/io/gnuplot.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "frnn/error.hpp"
#include "frnn/io/atomic_file.hpp"
#include "frnn/io/child_process.hpp"

namespace frnn::io {

std::string gnuplot_quoted(const std::string& text) {
    std::string out = "'";
    for (char ch : text) out += ch == '\'' ? std::string("''") : std::string(1, ch);
    return out + "'";
}

std::string gnuplot_data_block(const std::string& name, const std::vector<std::pair<double, double>>& points) {
    std::string block = name + " << EOD\n";
    for (const auto& [x, y] : points) {
        char line[64];
        std::snprintf(line, sizeof line, "%.10g %.10g\n", x, y);
        block += line;
    }
    return block + "EOD\n";
}

bool draw_with_gnuplot(const std::string& commands, int width, int height, const std::string& png_path,
                       std::string& why) {
    const std::string temp_png = temporary_path_beside(png_path).string() + ".png";
    const std::string script_path = temporary_path_beside(png_path).string() + ".gp";
    const std::string script = "set terminal pngcairo size " + std::to_string(width) + "," + std::to_string(height) +
                               " font ',10'\nset output " + gnuplot_quoted(temp_png) + "\n" + commands;
    write_file_atomically(script_path, script);
    const int status = run_program({"gnuplot", script_path});
    const int spawn_errno = errno;
    std::remove(script_path.c_str());
    if (status == -1) {
        why = "gnuplot not found (" + std::string(std::strerror(spawn_errno)) + "): install Debian's gnuplot-nox to get " +
              png_path;
        return false;
    }
    if (status != 0) {
        std::remove(temp_png.c_str());
        throw error("plot: gnuplot exited with status " + std::to_string(status) + " writing " + png_path);
    }
    commit_temporary(temp_png, png_path);
    return true;
}

}  // namespace frnn::io
