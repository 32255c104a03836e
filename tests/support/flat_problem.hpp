// A random problem of a scene with its flat input for the generated code (solver/flat_layout.hpp),
// drawn the same way by the generated-scene tests and the real-time tests.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
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
  p.in = solver::flat_input(p, s.flat_layout(chain));
  return p;
}

// The batch tests' states that part from their group of lanes (tests/test_batch.cpp and every
// bundled scene's BatchEqualsFlatSolves): every third state, in turn, gets the joints at q = 0
// (axes aligned: a rank-deficient constraint on most arms, so (C4)'s pivoted path), a NaN in one
// flat input (as many positions as there are inputs), the first torque driver 1000 times its range
// (saturation; a scene without one keeps the state), or, where at least two directions are
// run-time inputs, the second equal to the first (rank-deficient). The others are left as drawn.
template <class T>
void part_from_group(std::vector<T>& in, const solver::FlatLayout& layout, std::size_t state) {
  if (state % 3 != 0) return;
  switch ((state / 3) % 4) {
    case 0:
      for (std::size_t i = layout.floating_base ? 9 : 0; i < layout.positions(); ++i) in[layout.q() + i] = 0;
      break;
    case 1: in[(state / 12) % in.size()] = std::numeric_limits<T>::quiet_NaN(); break;
    case 2:
      if (layout.torques > 0)
        for (std::size_t i = 0; i < layout.dof; ++i) in[layout.torque(0) + i] *= 1000;
      break;
    default:
      if (layout.input_directions.size() > 1)
        std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(layout.alpha(0)), 6,
                    in.begin() + static_cast<std::ptrdiff_t>(layout.alpha(1)));
  }
}

}  // namespace sweepgen::test
