// PNG plots drawn by gnuplot (Debian gnuplot-nox) in a child process, for the benchmark report
// and the validation report.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace frnn::io {

/// `text` as a gnuplot single-quoted string (a quote inside is written twice).
std::string gnuplot_quoted(const std::string& text);

/// A named data block (`$name << EOD`, one "x y" line per point, `EOD`) for `plot $name`.
std::string gnuplot_data_block(const std::string& name, const std::vector<std::pair<double, double>>& points);

/// Draws `commands` (gnuplot commands: data blocks, settings, plot) into the PNG `png_path`,
/// width x height pixels (pngcairo, 10 pt font). The image is written under a temporary name
/// and renamed, so it is whole or absent. Returns false, with the reason in `why`, when gnuplot
/// is not installed; throws frnn::error when gnuplot fails.
bool draw_with_gnuplot(const std::string& commands, int width, int height, const std::string& png_path,
                       std::string& why);

}  // namespace frnn::io
