#include "cli/family_command.hpp"

#include <filesystem>
#include <iostream>

#include "cli/command_line.hpp"
#include "io/output_files.hpp"
#include "family/family.hpp"

namespace sweepgen::cli {

void add_family_command(CLI::App& app, FamilyOptions& options) {
  CLI::App* command = app.add_subcommand(
      "family", "Write the synthetic robots of the numerical-stability suite: DIR/<case>.urdf and DIR/<case>.yaml");
  command->add_option("--out", options.out, "output directory")->capture_default_str()->check(kNonEmptyPath);
  command->add_flag("--list", options.list, "list the cases and what each stresses, write nothing");
  command->add_option("--case", options.cases, "write only this case (repeatable)");
}

int run_family(const FamilyOptions& options) {
  if (options.list) {
    for (const auto& name : family::family_case_names()) {
      const family::FamilyCase c = family::family_case(name);
      std::cout << name << (c.heavy ? " [heavy]" : "") << ": " << c.purpose << "\n";
    }
    return 0;
  }
  const std::vector<std::string>& names = options.cases.empty() ? family::family_case_names() : options.cases;
  std::vector<family::FamilyCase> cases;
  for (const auto& name : names) cases.push_back(family::family_case(name));  // all names checked before writing
  std::error_code error;
  std::filesystem::create_directories(options.out, error);
  if (error) throw io::IoError(options.out, "cannot create directory (" + error.message() + ")");
  std::vector<io::OutputFile> files;
  for (const auto& c : cases) {
    const std::filesystem::path stem = std::filesystem::path(options.out) / c.name;
    files.push_back({stem.string() + ".urdf", family::urdf_text(c.robot)});
    files.push_back({stem.string() + ".yaml", family::scene_text(c)});
  }
  io::write_files_atomically(files);
  std::cout << "wrote " << cases.size() << " case(s) (URDF + scene each) to " << options.out << "\n";
  return 0;
}

}  // namespace sweepgen::cli
