// Running gnuplot for the report's PNG figures (Debian gnuplot-nox may lack pngcairo).
#pragma once

#include <string>

namespace sweepgen::report {

// The legend under the plot, its entries in as many columns as fit the width (beside the plot,
// the long variant names took half the figure's width from it), a line's room between it and the
// x axis's label.
inline constexpr const char* kKeyBelowPlot = "set key outside bottom center horizontal height 1";

// The `set terminal` line for a PNG of `width` x `height` pixels: pngcairo where this gnuplot
// has it, else png. Throws io::IoError when gnuplot cannot be run.
std::string png_terminal(const std::string& work_dir, int width, int height);

// Runs `gnuplot script_path` (its output in work_dir/gnuplot.log) and checks that it wrote a
// PNG to `png_path`; throws io::IoError with the log's tail otherwise.
void run_gnuplot(const std::string& script_path, const std::string& png_path, const std::string& work_dir);

// Writes `script_stem`.gp (the `body` of set commands and one plot command, drawn into
// `out_stem`.png and again into `out_stem`.svg) and runs it; throws io::IoError when gnuplot
// fails or either file is missing or not what it should be.
void draw_png_and_svg(const std::string& body, const std::string& out_stem, const std::string& script_stem,
                      const std::string& work_dir, int width, int height);

}  // namespace sweepgen::report
