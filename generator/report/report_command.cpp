#include "report/report_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <unistd.h>

#include "io/output_files.hpp"
#include "model/error.hpp"
#include "family/family.hpp"
#include "report/bundled_data.hpp"
#include "report/external_tools.hpp"
#include "report/flat_judgement.hpp"
#include "report/native_library.hpp"
#include "report/stability_cases.hpp"
#include "report/stability_command.hpp"
#include "report/study.hpp"
#include "report/study_output.hpp"
#include "report/text_format.hpp"
#include "scene/scene.hpp"

namespace sweepgen::report {
namespace {

namespace fs = std::filesystem;

// --quick: states per family and timed passes.
constexpr std::size_t kQuickStates = 6;
constexpr int kQuickRepetitions = 3;
// The scene --quick studies when none is given.
constexpr const char* kQuickScene = "robots/panda/panda_nc6.yaml";

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Every bundled scene (robots/*/*.yaml, report/bundled_data.hpp), sorted.
std::vector<std::string> bundled_scenes() {
  std::vector<std::string> scenes;
  const fs::path robots = bundled_data_dir() / "robots";
  std::error_code error;
  for (const auto& robot : fs::directory_iterator(robots, error))
    for (const auto& file : fs::directory_iterator(robot.path(), error))
      if (file.path().extension() == ".yaml") scenes.push_back(file.path().string());
  if (scenes.empty())
    throw InputError(robots.string(), "robots/*/*.yaml", "no bundled scenes found; give --scene FILE (or --urdf FILE)");
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

// Whether the report runs on its defaults (no scene, URDF or family case named).
bool by_default(const ReportOptions& options) {
  return options.scenes.empty() && options.urdf.empty() && options.family_cases.empty();
}

std::vector<std::string> family_cases_of(const ReportOptions& options) {
  std::vector<std::string> cases = options.family_cases;
  if (by_default(options) && !options.quick) cases = kStiffCases;
  for (const std::string& name : cases) family::family_case(name);  // throws InputError for an unknown name
  return cases;
}

std::vector<scene::Scene> load_scenes(const ReportOptions& options) {
  if (!options.urdf.empty()) return {scene::default_scene(options.urdf, options.root, options.tip, {}, true, "sweepgen report")};
  std::vector<std::string> files = options.scenes;
  if (by_default(options))
    files = options.quick ? std::vector<std::string>{(bundled_data_dir() / kQuickScene).string()}
                          : bundled_scenes();
  std::vector<scene::Scene> scenes;
  for (const std::string& file : files) scenes.push_back(scene::load_scene(file));
  for (std::size_t a = 0; a < scenes.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (scenes[a].solver == scenes[b].solver)
        throw InputError(scenes[a].path, "solver", "'" + scenes[a].solver + "' is also the solver of " +
                                                       scenes[b].path + "; the report names its files after it");
  return scenes;
}

// A directory the report's files are written into first and moved out of at the end, so that
// a failure leaves no half-written report (and the previous one, if any, intact).
class Staging {
 public:
  explicit Staging(const fs::path& out) : out_(out), dir_(out / (".staging-" + std::to_string(::getpid()))) {
    std::error_code error;
    fs::create_directories(dir_, error);
    if (error) throw io::IoError(dir_.string() + ": cannot create the output directory (" + error.message() + ")");
    const fs::path probe = dir_ / "probe";
    std::FILE* f = std::fopen(probe.c_str(), "w");
    const bool writable = f != nullptr && std::fclose(f) == 0;
    fs::remove_all(probe, error);
    if (!writable) {
      fs::remove_all(dir_, error);
      throw io::IoError(out.string() + ": not writable");
    }
  }
  ~Staging() {
    std::error_code error;
    fs::remove_all(dir_, error);
  }
  const fs::path& dir() const { return dir_; }
  // Moves the staged files into the output directory.
  void publish(const std::vector<std::string>& names) const {
    for (const std::string& name : names) {
      std::error_code error;
      fs::rename(dir_ / name, out_ / name, error);
      if (error) throw io::IoError((out_ / name).string() + ": cannot write (" + error.message() + ")");
    }
  }

 private:
  fs::path out_, dir_;
};

std::string setup_text(const ReportOptions& options) {
  return std::to_string(options.states) + " states per random family (seed " + std::to_string(options.seed) + "), " +
         std::to_string(options.repetitions) + " timed passes, compiler `" + options.cxx + "`; x86-64-v3 " +
         (cpu_supports(Isa::x86_64_v3) ? "available on this CPU (AVX2, FMA, BMI2)" : "not available on this CPU") + ".";
}

}  // namespace

void add_report_command(CLI::App& app, ReportOptions& options) {
  CLI::App* command = app.add_subcommand(
      "report", "Study scenes' generated solvers: every variant (policies, float/double, ISA, factorisation) next to "
                "the reference solver, KDL and a dense KKT, on named state families; error against a binary128 "
                "referee and time per call; report.md with figures and a recommendation per scene");
  command->add_option("--scene", options.scenes, "scene file (YAML), repeatable; default: every bundled scene");
  command->add_option("--urdf", options.urdf, "URDF file (instead of --scene: the default scene for it)");
  command->add_option("--family", options.family_cases,
                      "a synthetic robot of `sweepgen family` (e.g. mass_ratio_heavy_tool), repeatable; without "
                      "--scene, --urdf, --family and --quick: every bundled scene and the stiff mass-ratio arms");
  command->add_option("--root", options.root, "root link (with --urdf)");
  command->add_option("--tip", options.tip, "tip link (with --urdf)");
  command->add_option("--states", options.states, "states per random state family")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command->add_flag("--quick", options.quick,
                    "a report in seconds: " + std::to_string(kQuickStates) + " states per family and " +
                        std::to_string(kQuickRepetitions) +
                        " timed passes unless --states and --repetitions say otherwise, one compile per scene (no x86-64-v3 or other-factorisation row); without "
                        "--scene only " + kQuickScene);
  command->add_option("--out", options.out,
                      "output directory: report.md, report.csv, states.csv, <scene>_{time,kappa}.{png,svg}, build/ "
                      "(default: report); with --stability stability.csv, stability.png, build/ (default: stability)");
  command->add_option("--seed", options.seed, "random seed")->capture_default_str();
  command->add_option("--repetitions", options.repetitions, "timed passes over all states")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command->add_option("--cxx", options.cxx, "C++ compiler for the generated code")->capture_default_str();
  command->add_flag("--stability", options.stability,
                    "instead: error against condition number on the stability suite's cases and extreme states, per "
                    "ill-conditioning policy (pivoted_ldlt, damped) and variant (docs/stability.md)");
  command->add_option("--cases", options.cases,
                      "with --stability: these cases (comma-separated; family cases and panda_nc6, iiwa14_nc6, ur5_nc6, "
                      "planar_nc2; default: all but the heavy ones)")
      ->delimiter(',');
  command->add_option("--states-per-kind", options.states_per_kind, "with --stability: states per random kind")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command->add_flag("--full", options.full, "with --stability: the heavy cases (100 and 300 joints) too");
  command->add_option("--judge", options.judge,
                      "with one --scene: instead, judge the flat results in FILE (a line per state: the scene's flat "
                      "input, then a solver's flat output, e.g. from a GPU: bench/gpu/run.sh) against the binary128 "
                      "referee; exit 4 where a state misses the bound");
  command->parse_complete_callback([command, &options] {
    if (!options.judge.empty()) {
      if (options.scenes.size() != 1) throw CLI::ValidationError("--judge needs exactly one --scene (the results' scene)");
      for (const char* other : {"--urdf", "--family", "--stability", "--quick", "--states", "--repetitions", "--out"})
        if (command->count(other) > 0) throw CLI::ValidationError(std::string(other) + " does not go with --judge");
    }
    if (options.stability) {
      for (const char* other :
           {"--scene", "--urdf", "--root", "--tip", "--states", "--repetitions", "--quick", "--family"})
        if (command->count(other) > 0)
          throw CLI::ValidationError(std::string(other) + " does not go with --stability (it measures its own cases)");
      if (options.full && !options.cases.empty()) throw CLI::ValidationError("give --full or --cases, not both");
      return;
    }
    for (const char* stability_only : {"--cases", "--states-per-kind", "--full"})
      if (command->count(stability_only) > 0)
        throw CLI::ValidationError(std::string(stability_only) + " goes with --stability");
    if (!options.scenes.empty() && !options.urdf.empty()) throw CLI::ValidationError("give --scene or --urdf, not both");
    if (options.urdf.empty() && (!options.root.empty() || !options.tip.empty()))
      throw CLI::ValidationError("--root and --tip go with --urdf (a scene file names its own)");
    // --quick's fewer states and passes are defaults: a --states or --repetitions beside it counts.
    if (options.quick && command->count("--states") == 0) options.states = kQuickStates;
    if (options.quick && command->count("--repetitions") == 0) options.repetitions = kQuickRepetitions;
  });
}

int run_report(const ReportOptions& options) {
  if (!options.judge.empty())
    return judge_flat_results(scene::load_scene(options.scenes.front()), options.judge, std::cout).passed() ? 0 : 4;
  if (options.stability)
    return run_stability_report({options.cases, options.states_per_kind, options.full, options.seed,
                                 options.out.empty() ? "stability" : options.out, options.cxx});
  const auto started = std::chrono::steady_clock::now();
  std::vector<scene::Scene> scenes = load_scenes(options);  // every input error before any work
  std::vector<model::Chain> chains;
  for (const scene::Scene& s : scenes) chains.push_back(scene::load_scene_chain(s));
  const std::vector<std::string> family_cases = family_cases_of(options);

  const fs::path out = fs::absolute(options.out.empty() ? "report" : options.out);
  const Staging staging(out);
  std::cerr << "[report] " << scenes.size() + family_cases.size() << " scene(s):";
  for (const scene::Scene& s : scenes) std::cerr << " " << (s.path.empty() ? s.chain.urdf : s.path);
  for (const std::string& name : family_cases) std::cerr << " --family " << name;
  std::cerr << std::endl;
  check_external_tools(options.cxx, staging.dir().string());
  const fs::path family_dir = out / "build" / "family";
  if (!family_cases.empty()) fs::create_directories(family_dir);
  for (const std::string& name : family_cases) {
    StabilityCase c = family_stability_case(name, family_dir);
    scenes.push_back(std::move(c.scene));
    chains.push_back(std::move(c.chain));
  }
  std::vector<SceneStudy> studies;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const std::string where = "[" + std::to_string(k + 1) + "/" + std::to_string(scenes.size()) + " " +
                              scenes[k].solver + "] ";
    StudyOptions study_options{options.states, options.repetitions, options.seed, options.cxx, out / "build" / scenes[k].solver,
                               options.quick, [&](const std::string& what) {
                                 std::cerr << where << what << " (" << seconds(seconds_since(started)) << ")"
                                           << std::endl;
                               }};
    studies.push_back(study_scene(scenes[k], chains[k], study_options));
    print_study(studies.back(), std::cout);
  }

  std::cerr << "[report] figures (gnuplot), report.md, report.csv, states.csv" << std::endl;
  const fs::path plots = out / "build" / "plots";
  fs::create_directories(plots);
  std::vector<std::string> files = draw_figures(studies, staging.dir(), plots);
  std::ostringstream command;
  command << "sweepgen report";
  for (std::size_t k = 0; k + family_cases.size() < scenes.size(); ++k)
    command << (scenes[k].path.empty() ? " --urdf " + scenes[k].chain.urdf : " --scene " + scenes[k].path);
  for (const std::string& name : family_cases) command << " --family " << name;
  if (options.quick) command << " --quick";
  io::write_files_atomically({{(staging.dir() / "report.md").string(),
                               report_markdown(studies, command.str(), setup_text(options))},
                              {(staging.dir() / "report.csv").string(), report_csv(studies)},
                              {(staging.dir() / "states.csv").string(), states_csv(studies)}});
  files.insert(files.end(), {"report.csv", "states.csv", "report.md"});  // report.md last: the report is whole
  staging.publish(files);
  std::cout << "\nwrote " << (out / "report.md").string() << " with " << files.size() - 1 << " more files (in "
            << seconds(seconds_since(started)) << ")\n";
  return 0;
}

}  // namespace sweepgen::report
