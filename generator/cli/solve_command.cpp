#include "cli/solve_command.hpp"

#include <fstream>
#include <functional>
#include <iostream>

#include "cli/json_problem.hpp"
#include "cli/scene_problem.hpp"
#include "model/error.hpp"
#include "model/input_limits.hpp"
#include "model/urdf_loader.hpp"
#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::cli {
namespace {

std::map<std::string, double> parse_rotor_inertia(const std::vector<std::string>& entries) {
  std::map<std::string, double> values;
  for (const auto& entry : entries) {
    const auto eq = entry.find('=');
    std::size_t used = 0;
    double value = 0;
    try {
      if (eq == std::string::npos) throw std::invalid_argument("no '='");
      value = std::stod(entry.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (eq == std::string::npos || eq == 0 || used == 0 || used != entry.size() - eq - 1)
      throw InputError("--rotor-inertia", quote_name(entry), "expected JOINT=VALUE with a number VALUE");
    values[entry.substr(0, eq)] = value;
  }
  return values;
}

// The reference solver for one problem: one torque instance, one external-force instance per
// loaded link, Nc = number of directions, drivers kept apart (Alg. 2).
nlohmann::ordered_json solve_problem(const Problem& p, const model::Chain& chain) {
  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  for (const auto& [link, wrench] : p.f_ext) layout.external_forces.push_back({link, link});
  layout.constraints = p.alpha.size();
  layout.sets = p.sets;
  layout.decompose_all();
  if (const std::string problem = solver::too_many_directions(layout, chain); !problem.empty())
    throw KeyError("constraints", problem);
  solver::ReferenceSolver<double> solver(chain, layout);
  solver.outward(p.q, p.qd, p.base_rotation);
  auto& drivers = solver.drivers();
  drivers.torques[0] = p.tau_ff;
  std::size_t k = 0;
  for (const auto& [link, wrench] : p.f_ext) drivers.external_forces[k++] = wrench;
  for (std::size_t c = 0; c < p.alpha.size(); ++c) drivers.constraint_directions[c] = p.alpha[c];
  solver.decompose();
  solver::ConstraintVector<double> beta = p.beta.size() ? solver::ConstraintVector<double>(p.beta) : solver::ConstraintVector<double>(0);
  const auto& solution = solver.solve(p.policy, beta);
  return solution_to_json(solution, solver.status(), chain, p.sets);
}

enum class LineRead { line, end, too_long };

// One line of `in` into `text` (without its '\n'), reading at most `limit` bytes of it.
LineRead read_line(std::istream& in, std::string& text, std::size_t limit) {
  text.clear();
  for (std::streambuf* buffer = in.rdbuf();;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) return text.empty() ? LineRead::end : LineRead::line;
    if (c == '\n') return LineRead::line;
    if (text.size() == limit) return LineRead::too_long;
    text += static_cast<char>(c);
  }
}

}  // namespace

void add_solve_command(CLI::App& app, SolveOptions& options) {
  CLI::App* solve = app.add_subcommand("solve", "Solve JSON-line problems with the reference solver");
  solve->add_option("--scene", options.scene,
                    "scene file: solve the scene's own problem (its chain, gravity, locked joints, drivers by name, "
                    "fixed directions, policies and outputs); no chain flag beside it");
  // No CLI::ExistingFile check: a missing URDF is bad input (exit 1, reported by the loader),
  // not a usage error.
  solve->add_option("--urdf", options.urdf, "URDF file (without --scene)");
  solve->add_option("--root", options.root, "root link (default: the URDF's root)");
  solve->add_option("--tip", options.tip, "tip link (default: the deepest link of a single chain)");
  solve->add_option("--branch-tip", options.branch_tips,
                    "a further tip (repeatable): the moving joints on the paths to every tip form a tree");
  solve->add_flag("--floating-base", options.floating_base,
                  "the root link moves freely (docs/derivation.md, F5): q starts with world_R_base (9, row-major), "
                  "qd, tau_ff and qdd with the base's six coordinates");
  solve->add_flag("--no-snap-quarter-turns", options.literal_angles,
                  "take URDF angles as written, not within 1e-10 rad of a multiple of pi/2 as exact (docs/derivation.md, F2)");
  solve->add_option("--mimic", options.mimic,
                    "independent: each <mimic> joint a joint of its own (the default); coupled: held to its source "
                    "exactly (docs/derivation.md, M1): q and qd without it, coupling_torque by joint in the answer")
      ->check(CLI::IsMember({"independent", "coupled"}));
  solve->add_option("--input", options.input, "file of JSON lines, or - for standard input")->capture_default_str();
  solve->add_option("--rotor-inertia", options.rotor_inertia, "JOINT=VALUE rotor inertia (repeatable)");
  // A scene states its chain: a chain flag beside it would solve another problem than the scene's
  // generated solver does, so the two together are a usage error (exit 2), as is neither.
  solve->parse_complete_callback([solve, &options] {
    if (options.scene.empty() && options.urdf.empty()) throw CLI::RequiredError("--scene or --urdf");
    if (options.scene.empty()) return;
    for (const char* flag : {"--urdf", "--root", "--tip", "--branch-tip", "--floating-base", "--no-snap-quarter-turns",
                             "--rotor-inertia", "--mimic"})
      if (solve->count(flag) > 0)
        throw CLI::ValidationError(std::string(flag) + " and --scene",
                                   "the scene states the chain; change it there, or drop --scene");
  });
}

namespace {

// The answer to one parsed line: the scene's problem, or the problem the line states for the
// chain of --urdf (json_problem.hpp).
using Answer = std::function<nlohmann::ordered_json(const nlohmann::json&)>;

int answer_lines(const SolveOptions& options, const Answer& answer) {
  std::ifstream file;
  if (options.input != "-") {
    file.open(options.input);
    if (!file) throw InputError(options.input, "file", "cannot be opened for reading");
  }
  std::istream& in = options.input == "-" ? std::cin : file;
  const std::string source = options.input == "-" ? "<stdin>" : options.input;

  int exit_code = 0;
  const auto report = [&](std::size_t line, const std::string& reason) {
    const std::string message = source + ":" + std::to_string(line) + ": " + reason;
    std::cerr << "sweepgen: error: " << message << "\n";
    std::cout << error_line(line, message) << "\n";
    exit_code = 1;
  };
  std::string text;
  for (std::size_t line = 1;; ++line) {
    const LineRead read = read_line(in, text, kMaxSolveLineBytes);
    if (read == LineRead::end) break;
    if (read == LineRead::too_long) {  // its end may never come (/dev/zero): stop reading
      report(line, "line longer than " + size_text(kMaxSolveLineBytes) +
                       ", the limit (README, \"Limits\"); the input is not read further");
      break;
    }
    // Answered like any line that is not a problem, so that answers and lines pair one to one.
    if (text.find_first_not_of(" \t\r") == std::string::npos) {
      report(line, "a blank line; each line is one problem, a JSON object");
      continue;
    }
    try {
      const nlohmann::json parsed = nlohmann::json::parse(text);
      refuse_hidden_json(text);
      std::cout << json_text(answer(parsed)) << "\n";
    } catch (const nlohmann::json::parse_error& e) {
      report(line, json_error_reason(e));
    } catch (const std::exception& e) {
      report(line, e.what());
    }
  }
  return exit_code;
}

}  // namespace

int run_solve(const SolveOptions& options) {
  if (!options.scene.empty()) {
    const scene::Scene s = scene::load_scene(options.scene);
    const model::Chain chain = scene::load_scene_chain(s);
    SceneSolve scene_solve(s, chain);
    return answer_lines(options, [&](const nlohmann::json& line) { return scene_solve.answer(line); });
  }
  model::ChainSpec spec;
  spec.urdf = options.urdf;
  spec.root_link = options.root;
  spec.tip_link = options.tip;
  spec.branch_tips = options.branch_tips;
  spec.floating_base = options.floating_base;
  spec.snap_quarter_turns = !options.literal_angles;
  spec.couple_mimics = options.mimic == "coupled";
  spec.rotor_inertia = parse_rotor_inertia(options.rotor_inertia);
  spec.naming_the_tip = "sweepgen solve --urdf " + options.urdf + " --tip LINK (for a tree, --branch-tip LINK for each further tip)";
  const model::Chain chain = model::load_chain(spec);
  return answer_lines(options, [&](const nlohmann::json& line) { return solve_problem(parse_problem(line, chain), chain); });
}

}  // namespace sweepgen::cli
