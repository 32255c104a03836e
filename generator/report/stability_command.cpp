#include "report/stability_command.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include "io/output_files.hpp"
#include "family/family.hpp"
#include "model/error.hpp"
#include "report/bundled_data.hpp"
#include "report/external_tools.hpp"
#include "report/stability_output.hpp"
#include "report/text_format.hpp"

namespace sweepgen::report {
namespace {

// The bundled scene files by case name (their file stem, which is their solver name).
std::string bundled_scene_file(const std::string& name) {
  for (const auto& file : bundled_stability_scenes())
    if (std::filesystem::path(file).stem() == name) return file;
  return "";
}

std::vector<std::string> selected_cases(const StabilityOptions& options) {
  if (options.cases.empty()) {
    std::vector<std::string> names;
    for (const auto& name : family::family_case_names())
      if (options.full || !family::family_case(name).heavy) names.push_back(name);
    for (const auto& file : bundled_stability_scenes()) names.push_back(std::filesystem::path(file).stem().string());
    return names;
  }
  // Every name checked before anything is written.
  const std::vector<std::string> known = stability_case_names();
  for (const auto& name : options.cases)
    if (std::find(known.begin(), known.end(), name) == known.end())
      throw InputError("sweepgen report --stability", "--cases '" + name + "'",
                       "no such case (the family's, see `sweepgen family --list`, or a bundled scene: panda_nc6, "
                       "iiwa14_nc6, ur5_nc6, planar_nc2)" +
                           nearest_name_hint(name, known));
  return options.cases;
}

StabilityCase load_case(const std::string& name, const std::filesystem::path& build_dir) {
  std::error_code error;
  std::filesystem::create_directories(build_dir, error);
  if (error) throw io::IoError(build_dir.string() + ": cannot create directory (" + error.message() + ")");
  const std::string bundled = bundled_scene_file(name);
  if (!bundled.empty()) return bundled_stability_case(bundled, bundled_data_dir());
  return family_stability_case(name, build_dir);
}

}  // namespace

std::vector<std::string> stability_case_names() {
  std::vector<std::string> names = family::family_case_names();
  for (const auto& file : bundled_stability_scenes()) names.push_back(std::filesystem::path(file).stem().string());
  return names;
}

int run_stability_report(const StabilityOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const std::vector<std::string> cases = selected_cases(options);
  const std::filesystem::path out_dir = std::filesystem::absolute(options.out);
  // Every case loaded (its scene and URDF read and checked) and the tools found before any is measured.
  std::vector<StabilityCase> loaded;
  for (const std::string& name : cases) loaded.push_back(load_case(name, out_dir / "build" / name));
  check_external_tools(options.cxx, (out_dir / "build").string());
  std::vector<StabilityRow> rows;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string where = "[" + std::to_string(i + 1) + "/" + std::to_string(cases.size()) + "] " + cases[i];
    std::cerr << where << ": extreme states (" << options.states_per_kind
              << " per random kind), binary128 referees for both policies, double and float..." << std::endl;
    const std::filesystem::path build_dir = out_dir / "build" / cases[i];
    const StabilityCase& c = loaded[i];
    StabilityRunOptions run;
    run.states_per_kind = options.states_per_kind;
    run.seed = options.seed;
    run.cxx = options.cxx;
    run.build_dir = build_dir;
    run.progress = [&where](const std::string& policy) {
      return CompileProgress{
          [&where, policy](int step, const std::string& what) {
            std::cerr << where << ", " << policy << " [" << step << "/3] " << what << std::endl;
          },
          [](const std::string& what) { std::cerr << "      " << what << std::endl; }};
    };
    const std::vector<StabilityRow> case_rows = measure_stability_case(c, run);
    rows.insert(rows.end(), case_rows.begin(), case_rows.end());
  }

  const std::string csv = (out_dir / "stability.csv").string();
  const std::string png = (out_dir / "stability.png").string();
  std::cerr << "writing " << csv << " and " << png << " (gnuplot)" << std::endl;
  io::write_files_atomically({{csv, stability_csv_text(rows)}});
  std::cout << "sweepgen report --stability: " << cases.size() << " case(s), policies pivoted_ldlt and damped, "
            << options.states_per_kind << " states per random kind (seed " << options.seed << ")\n"
            << "errors against ReferenceSolver<Quad> (binary128) with the same factorisation and the scalar's "
               "tolerances; kappa = max(1, cond_s(E), 1/min rho_D); full rank: neither the variant nor the referee "
               "dropped a direction or locked a joint\n\n";
  print_stability_table(rows, std::cout);
  plot_stability(rows, (out_dir / "build").string(), png);
  std::cout << "\nwrote " << csv << " and " << png << " (in "
            << seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()) << ")\n";
  return 0;
}

}  // namespace sweepgen::report
