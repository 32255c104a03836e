#include "report/gnuplot.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/output_files.hpp"
#include "report/native_library.hpp"

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

}  // namespace sweepgen::report
