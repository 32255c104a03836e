// A random problem of a scene with its flat input for the generated code (solver/flat_layout.hpp),
// drawn the same way by the generated-scene tests and the real-time tests.
#pragma once

#include <vector>

#include "scene/scene.hpp"
#include "solver/flat_layout.hpp"
#include "support/random_problem.hpp"

namespace sweepgen::test {

// One random problem of a scene, and its flat input for the generated code.
struct FlatProblem : solver::SolveInputs<double> {
  std::vector<double> in;
};

inline FlatProblem random_flat_problem(RandomProblem& random, const scene::Scene& s, const model::Chain& chain) {
  FlatProblem p;
  p.q = random.positions(chain);
  p.qd = random.velocities(chain);
  const std::size_t nc = s.layout.constraints;
  for (std::size_t t = 0; t < s.layout.torques.size(); ++t) p.torques.push_back(random.torques(chain, t == 0 ? 1.5 : 0.2));
  for (std::size_t e = 0; e < s.layout.external_forces.size(); ++e) p.wrenches.push_back(random.wrench());
  p.alpha = solver::directions_with(s.layout, [&random] { return random.unit_direction(); });
  p.beta.resize(nc);
  for (auto& b : p.beta) b = random.uniform(-3, 3);
  if (chain.floating_base) p.base_rotation = random.rotation();
  p.in = solver::flat_input(p, s.flat_layout(chain.dof()));
  return p;
}

}  // namespace sweepgen::test
