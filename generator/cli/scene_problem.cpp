#include "cli/scene_problem.hpp"

#include "cli/json_problem.hpp"

namespace sweepgen::cli {
namespace {

using nlohmann::json;

// What solution_to_json calls each result the scene's `outputs` key lists.
const std::vector<std::pair<const char*, const char*>> kOutputKeys = {
    {"qdd", "qdd"}, {"tau_cmd", "tau_cmd"}, {"tau_ctrl", "tau_ctrl"}, {"nu", "nu"},
    {"tip_acceleration", "xdd_tip"}, {"set_acceleration", "xdd_links"}, {"closure_error", "closure_error"},
    {"coupling_torque", "coupling_torque"}};

// The keys a line may hold for this scene: its drivers by name, or "flat" alone with "policy".
std::vector<std::string> keys_of(const solver::DriverLayout& drivers) {
  std::vector<std::string> keys{"q", "qd", "alpha", "beta", "policy", "flat"};
  keys.insert(keys.end(), drivers.torques.begin(), drivers.torques.end());
  for (const auto& force : drivers.external_forces) keys.push_back(force.name);
  return keys;
}

void copy_into(const Eigen::VectorXd& values, std::vector<double>& flat, std::size_t offset) {
  std::copy(values.data(), values.data() + values.size(), flat.begin() + static_cast<std::ptrdiff_t>(offset));
}

}  // namespace

SceneSolve::SceneSolve(const scene::Scene& scene, const model::Chain& chain)
    : scene_(scene),
      chain_(chain),
      layout_(scene.flat_layout(chain)),
      solver_(chain, scene.layout, scene.solver_options()) {}

// The flat input (solver/flat_layout.hpp) of a line: "flat" as it is, or the named values at
// their places; a driver not named is zero, and so is β where "beta" is missing.
std::vector<double> SceneSolve::flat_input(const json& line) const {
  const std::vector<std::string> keys = keys_of(scene_.layout);
  for (const auto& [key, value] : line.items())
    if (std::find(keys.begin(), keys.end(), key) == keys.end())
      throw KeyError(key, "not an input of scene " + quote_name(scene_.solver) + nearest_name_hint(key, keys));
  if (line.contains("flat")) {
    for (const auto& [key, value] : line.items())
      if (key != "flat" && key != "policy") throw KeyError(key, "give either \"flat\" or the named inputs, not both");
    const Eigen::VectorXd flat = numbers(line["flat"], "flat", layout_.in_size());
    if (layout_.floating_base) base_rotation(flat, "flat");
    return std::vector<double>(flat.data(), flat.data() + flat.size());
  }
  std::vector<double> flat(layout_.in_size(), 0.0);
  for (const char* key : {"q", "qd"})
    if (!line.contains(key)) throw KeyError(key, "missing");
  const Eigen::VectorXd q = numbers(line["q"], "q", layout_.positions());
  if (layout_.floating_base) base_rotation(q, "q");
  copy_into(q, flat, layout_.q());
  copy_into(numbers(line["qd"], "qd", layout_.velocities()), flat, layout_.qd());
  for (std::size_t t = 0; t < scene_.layout.torques.size(); ++t)
    if (const std::string& name = scene_.layout.torques[t]; line.contains(name))
      copy_into(numbers(line[name], name, layout_.dof), flat, layout_.torque(t));
  for (std::size_t e = 0; e < scene_.layout.external_forces.size(); ++e)
    if (const std::string& name = scene_.layout.external_forces[e].name; line.contains(name))
      copy_into(numbers(line[name], name, 6), flat, layout_.external_force(e));
  const std::size_t run_time = layout_.input_directions.size();
  if (run_time > 0 && !line.contains("alpha"))
    throw KeyError("alpha", "missing: the scene's sets have " + std::to_string(run_time) + " run-time directions");
  if (line.contains("alpha")) {
    const json& alpha = line["alpha"];
    if (run_time == 0) throw KeyError("alpha", "the scene fixes every constraint direction");
    if (!alpha.is_array() || alpha.size() != run_time)
      throw KeyError("alpha", "expected " + std::to_string(run_time) + " directions, each [mx,my,mz,fx,fy,fz]");
    for (std::size_t j = 0; j < run_time; ++j)
      copy_into(numbers(alpha[j], "alpha[" + std::to_string(j) + "]", 6), flat, layout_.alpha(j));
  }
  if (line.contains("beta")) copy_into(numbers(line["beta"], "beta", layout_.constraints), flat, layout_.beta());
  return flat;
}

// "policy", one of the scene's; its first where the line names none.
solver::Policy SceneSolve::policy(const json& line) const {
  if (!line.contains("policy")) return scene_.policies.front();
  std::string listed;
  for (solver::Policy p : scene_.policies) listed += std::string(listed.empty() ? "" : ", ") + solver::name(p);
  const json& value = line["policy"];
  const auto parsed = value.is_string() ? solver::policy_from_name(value.get<std::string>()) : std::nullopt;
  if (!parsed || std::find(scene_.policies.begin(), scene_.policies.end(), *parsed) == scene_.policies.end())
    throw KeyError("policy", "expected one of the scene's policies: " + listed);
  return *parsed;
}

nlohmann::ordered_json SceneSolve::answer(const json& line) {
  if (!line.is_object()) throw KeyError("(line)", "expected a JSON object");
  const std::vector<double> in = flat_input(line);
  const solver::Policy chosen = policy(line);
  const auto& solution = solver_.run(solver::solve_inputs_from_flat(in.data(), layout_, scene_.layout), chosen);
  // The sets that name their link report its acceleration (the tip set of the short forms does not).
  std::vector<solver::ConstraintSet> listed;
  for (const auto& set : scene_.layout.sets)
    if (!set.link.empty()) listed.push_back(set);
  nlohmann::ordered_json result = solution_to_json(solution, solver_.status(), chain_, listed);
  for (const auto& [output, key] : kOutputKeys)
    if (!layout_.outputs.lists(output)) result.erase(key);
  std::vector<double> out(layout_.out_size(), 0.0);
  solver::flat_output(solution, solver_.status(), layout_, out.data());
  result["flat"] = out;
  return result;
}

}  // namespace sweepgen::cli
