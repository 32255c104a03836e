#include "report/external_tools.hpp"

#include "io/output_files.hpp"
#include "report/gnuplot.hpp"
#include "report/native_library.hpp"

namespace sweepgen::report {

void check_external_tools(const std::string& cxx, const std::string& work_dir) {
  const std::string log = work_dir + "/compiler-version.txt";
  const int status = run_process({cxx, "--version"}, log);
  if (status != 0)
    throw io::IoError("the C++ compiler `" + cxx + "` (--cxx) cannot be run" +
                      (status < 0 ? std::string(cxx.find('/') == std::string::npos ? " (not found on PATH)" : " (no such program)") : " (`" + cxx + " --version` exited " +
                                                                              std::to_string(status) + ")") +
                      "; the report compiles every generated solver with it");
  png_terminal(work_dir, 640, 480);  // throws when gnuplot cannot be run
}

}  // namespace sweepgen::report
