#include "report/gnuplot.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/output_files.hpp"
#include "report/native_library.hpp"
#include "report/text_format.hpp"

namespace sweepgen::report {

std::string png_terminal(const std::string& work_dir, int width, int height) {
  const std::string terminals_log = work_dir + "/gnuplot-terminals.txt";
  std::remove(terminals_log.c_str());
  if (run_process({"gnuplot", "-e", "set terminal"}, terminals_log) < 0)
    throw io::IoError("gnuplot: cannot be run (is gnuplot installed and on PATH?)");
  std::ifstream in(terminals_log);
  std::ostringstream terminals;
  terminals << in.rdbuf();
  const bool cairo = terminals.str().find("pngcairo") != std::string::npos;
  return std::string("set terminal ") + (cairo ? "pngcairo" : "png") + " size " + std::to_string(width) + "," +
         std::to_string(height) + " font 'Sans,11'\n";
}

void run_gnuplot(const std::string& script_path, const std::string& png_path, const std::string& work_dir) {
  const std::string log = work_dir + "/gnuplot.log";
  std::remove(log.c_str());
  std::remove(png_path.c_str());
  const int status = run_process({"gnuplot", script_path}, log);
  std::ifstream png(png_path, std::ios::binary);
  char signature[8] = {};
  png.read(signature, 8);
  if (status != 0 || !png || std::string(signature, 8) != "\x89PNG\r\n\x1a\n")
    throw io::IoError("gnuplot " + script_path + " failed (exit " + std::to_string(status) + ") to write " + png_path +
                       ":\n" + tail_of_file(log));
}

void draw_png_and_svg(const std::string& body, const std::string& out_stem, const std::string& script_stem,
                      const std::string& work_dir, int width, int height) {
  const std::string png = out_stem + ".png", svg = out_stem + ".svg", script = script_stem + ".gp";
  std::remove(svg.c_str());
  io::write_files_atomically(
      {{script, "# Written by `sweepgen report`: run `gnuplot " + script + "` to redraw.\n" +
                    png_terminal(work_dir, width, height) + "set output " + gnuplot_string(png) + "\n" + body +
                    "set terminal svg size " + std::to_string(width) + "," + std::to_string(height) +
                    " font 'Sans,11'\nset output " + gnuplot_string(svg) + "\nreplot\nunset output\n"}});
  run_gnuplot(script, png, work_dir);
  std::ifstream in(svg);
  std::string head(256, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (head.find("<svg") == std::string::npos)
    throw io::IoError("gnuplot " + script + " did not write " + svg + ":\n" + tail_of_file(work_dir + "/gnuplot.log"));
}

}  // namespace sweepgen::report
