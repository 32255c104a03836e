// `sweepgen generate` and `sweepgen info`.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sweepgen::cli {

// Where a scene comes from: a scene file, or a URDF with the default scene; flags override.
struct SceneOptions {
  std::string command;  // "sweepgen generate" or "sweepgen info", for messages
  std::string scene;
  std::string urdf;
  std::string root;
  std::string tip;
  std::string solver;
  std::string expose;
  std::vector<std::string> scalars;
  std::vector<std::string> branch_tips;
  bool floating_base = false;
  std::string mimic;            // --mimic: independent | coupled (scene key mimic)
  bool literal_angles = false;  // --no-snap-quarter-turns
  bool all_notes = false;       // --notes: every model note, not one line per kind
};

struct GenerateOptions {
  SceneOptions scene;
  std::string out = ".";
  std::string file_stem;
  std::string depfile;
  bool quiet = false;  // only warnings and errors
};

void add_generate_command(CLI::App& app, GenerateOptions& options);
void add_info_command(CLI::App& app, SceneOptions& options);

int run_generate(const GenerateOptions& options);
int run_info(const SceneOptions& options);

}  // namespace sweepgen::cli
