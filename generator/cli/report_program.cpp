#include "cli/report_program.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace sweepgen::cli {

int run_report_program(const std::vector<std::string>& args) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path program = self.parent_path() / kReportProgram;
  std::vector<std::string> words{program.string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  std::cerr << "sweepgen: error: `sweepgen report` runs " << program.string() << ", which cannot be run ("
            << std::strerror(errno) << "): build the target " << kReportProgram
            << " (cmake --build <build> --target " << kReportProgram << ", with -DSWEEPGEN_BUILD_REPORT=ON) or "
            << "install the package, which puts it beside sweepgen\n";
  return 3;
}

}  // namespace sweepgen::cli
