#include "report/report_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "io/output_files.hpp"
#include "model/error.hpp"
#include "report/compiled_solver.hpp"
#include "report/kdl_oracle.hpp"
#include "report/measure.hpp"
#include "report/native_library.hpp"
#include "report/report_output.hpp"
#include "report/stability_command.hpp"
#include "report/text_format.hpp"
#include "scene/scene.hpp"

namespace sweepgen::report {
namespace {

constexpr int kSteps = 5;

void progress(int step, const std::string& what) {
  std::cerr << "[" << step << "/" << kSteps << "] " << what << std::endl;
}
void detail(const std::string& what) { std::cerr << "      " << what << std::endl; }

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

scene::Scene resolve(const ReportOptions& options) {
  return report_scene(options.scene.empty() ? scene::default_scene(options.urdf, options.root, options.tip)
                                            : scene::load_scene(options.scene));
}

}  // namespace

void add_report_command(CLI::App& app, ReportOptions& options) {
  CLI::App* command = app.add_subcommand(
      "report", "Compile a scene's generated solver with the system compiler, load it, and measure its run time and "
                "error (original policy) next to the reference solver and KDL");
  command->add_option("--scene", options.scene, "scene file (YAML), e.g. robots/panda/panda_nc6.yaml");
  command->add_option("--urdf", options.urdf, "URDF file (instead of --scene: the default scene for it)");
  command->add_option("--root", options.root, "root link (with --urdf)");
  command->add_option("--tip", options.tip, "tip link (with --urdf)");
  command->add_option("--states", options.states, "random states")->capture_default_str()->check(CLI::Range(1, 100000000));
  command->add_option("--out", options.out,
                      "output directory: report.csv, report.png, build/ (default: report); with --stability "
                      "stability.csv, stability.png, build/ (default: stability)");
  command->add_option("--seed", options.seed, "random seed")->capture_default_str();
  command->add_option("--repetitions", options.repetitions, "timed passes over all states (>= 5)")
      ->capture_default_str()
      ->check(CLI::Range(5, 100000));
  command->add_option("--cxx", options.cxx, "C++ compiler for the generated code")->capture_default_str();
  command->add_flag("--stability", options.stability,
                    "instead of one scene: error against condition number on the stability suite's cases and extreme "
                    "states, per ill-conditioning policy (pivoted_ldlt, damped) and variant (docs/stability.md)");
  command->add_option("--cases", options.cases,
                      "with --stability: these cases (comma-separated; family cases and panda_nc6, iiwa14_nc6, ur5_nc6, "
                      "planar_nc2; default: all but the heavy ones)")
      ->delimiter(',');
  command->add_option("--states-per-kind", options.states_per_kind, "with --stability: states per random kind")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  command->add_flag("--full", options.full, "with --stability: the heavy cases (100 and 300 joints) too");
  command->parse_complete_callback([command, &options] {
    if (options.stability) {
      for (const char* other : {"--scene", "--urdf", "--root", "--tip", "--states", "--repetitions"})
        if (command->count(other) > 0)
          throw CLI::ValidationError(std::string(other) + " does not go with --stability (it measures its own cases)");
      if (options.full && !options.cases.empty()) throw CLI::ValidationError("give --full or --cases, not both");
      return;
    }
    for (const char* stability_only : {"--cases", "--states-per-kind", "--full"})
      if (command->count(stability_only) > 0)
        throw CLI::ValidationError(std::string(stability_only) + " goes with --stability");
    if (options.scene.empty() == options.urdf.empty()) throw CLI::ValidationError("give exactly one of --scene and --urdf");
    if (!options.scene.empty() && (!options.root.empty() || !options.tip.empty()))
      throw CLI::ValidationError("--root and --tip go with --urdf (a scene file names its own)");
  });
}

int run_report(const ReportOptions& options) {
  if (options.stability)
    return run_stability_report({options.cases, options.states_per_kind, options.full, options.seed,
                                 options.out.empty() ? "stability" : options.out, options.cxx});
  const auto started = std::chrono::steady_clock::now();
  const scene::Scene s = resolve(options);
  const model::Chain chain = scene::load_scene_chain(s);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const std::filesystem::path out_dir = std::filesystem::absolute(options.out.empty() ? "report" : options.out);
  const std::filesystem::path build_dir = out_dir / "build";
  const CompiledSolver compiled = compile_scene_solver(s, chain, build_dir, options.cxx, {progress, detail});
  const std::vector<std::string>& command = compiled.command;

  // 4. Measure.
  progress(4, "measuring on " + std::to_string(options.states) + " random states (seed " + std::to_string(options.seed) +
                  "), " + std::to_string(options.repetitions) + " timed passes each after a warm-up");
  const std::vector<Problem> problems = random_problems(s, chain, options.states, options.seed);
  TimingOptions timing;
  timing.repetitions = options.repetitions;
  detail("high-precision reference (ReferenceSolver<Quad>, IEEE binary128)...");
  const std::vector<Truth> truth = precise_reference(s, chain, problems);
  std::vector<VariantResult> results;
  detail("reference double (ReferenceSolver<double>)...");
  results.push_back(measure_reference_double(s, chain, problems, timing));
  detail("generated double...");
  results.push_back(
      measure_generated<double>(compiled.solve_f64_of.at(solver::Policy::original), "double", n, nc, problems, timing));
  detail("generated float...");
  results.push_back(measure_generated<float>(compiled.solve_f32, "float", n, nc, problems, timing));
  detail("KDL ChainHdSolver_Vereshchagin...");
  results.push_back(measure_kdl(s, chain, problems, timing));
  if (!results.back().note.empty()) detail("KDL: " + results.back().note);

  // 5. Table, CSV, plot.
  std::vector<ReportRow> rows;
  for (const auto& r : results) rows.push_back({&r, r.note.empty() ? summarize(r, problems, truth) : Summary{}});
  const std::string csv = (out_dir / "report.csv").string();
  const std::string png = (out_dir / "report.png").string();
  progress(5, "writing " + csv + " and " + png + " (gnuplot)");
  io::write_files_atomically({{csv, csv_text(rows)}});

  const std::size_t ill = rows.front().summary.ill_conditioned_states;
  std::cout << "sweepgen report: " << s.solver << " (" << (s.path.empty() ? "default scene for " + s.chain.urdf : s.path)
            << "), " << n << " joints, Nc = " << nc << ", policy original\n"
            << options.states << " random states (seed " << options.seed << "); time per solve (outward + decompose + "
            << "solve) over " << options.repetitions << " passes after a warm-up: median and p90\n"
            << "errors against ReferenceSolver<Quad> (" << std::numeric_limits<Precise>::digits
            << "-bit mantissa) over the " << options.states - ill << " states with cond(E^A_cstr,0) <= 1e6; "
            << ill << " states beyond\n"
            << "generated code: " << command_line(command) << "\n\n";
  print_table(rows, std::cout);
  for (const auto& row : rows)
    if (row.result->note.empty() && row.summary.rank_deficient_well_conditioned > 0)
      std::cout << "note: " << row.result->variant << " " << row.result->scalar << " reported constraint_rank_deficient in "
                << row.summary.rank_deficient_well_conditioned
                << " of the states with cond <= 1e6 (a pivot below its tolerance, 1000 eps of " << row.result->scalar
                << " by default, left a direction unenforced); max rel. error of qdd over the others: "
                << (row.summary.rank_deficient_well_conditioned + ill < options.states
                        ? scientific(static_cast<double>(row.summary.max_rel_err_qdd_full_rank))
                        : std::string("n/a (none)"))
                << "\n";
  plot(rows,
       s.solver + ": max relative qdd error vs time per solve (policy original, " + std::to_string(options.states) +
           " states, seed " + std::to_string(options.seed) + ")",
       build_dir.string(), png);
  std::cout << "\nwrote " << csv << " and " << png << " (in " << seconds(seconds_since(started)) << ")\n";
  return 0;
}

}  // namespace sweepgen::report
