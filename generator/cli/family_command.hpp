// `sweepgen family`: writes the numerical-stability suite's synthetic robots (URDF + scene per
// case; robots/family/README.md).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace sweepgen::cli {

struct FamilyOptions {
  std::string out = "family";
  bool list = false;
  std::vector<std::string> cases;  // empty: all
};

void add_family_command(CLI::App& app, FamilyOptions& options);
int run_family(const FamilyOptions& options);

}  // namespace sweepgen::cli
