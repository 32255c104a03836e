// One line of `sweepgen solve --scene` input and output (README, "sweepgen solve"): the scene's
// own problem, its drivers by their names or the generated solver's flat input, answered by the
// reference solver with the scene's options, its outputs and, as the generated solver writes
// them, the flat output.
#pragma once

#include <nlohmann/json.hpp>

#include "model/chain.hpp"
#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::cli {

class SceneSolve {
 public:
  SceneSolve(const scene::Scene& scene, const model::Chain& chain);

  // The answer to one input line; throws KeyError naming the offending key.
  nlohmann::ordered_json answer(const nlohmann::json& line);

 private:
  std::vector<double> flat_input(const nlohmann::json& line) const;
  solver::Policy policy(const nlohmann::json& line) const;

  const scene::Scene& scene_;
  const model::Chain& chain_;
  solver::FlatLayout layout_;
  solver::ReferenceSolver<double> solver_;
};

}  // namespace sweepgen::cli
