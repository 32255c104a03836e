// Seeded random inputs for the benchmarks (the same recipe as tests/support/generated_check.hpp,
// kept separate so bench/ does not depend on the test helpers), as solver::SolveInputs and in the
// generated code's flat order (solver/flat_layout.hpp). q within the joint limits, qd in [-2, 2] rad/s, the first torque instance up to 1.5x the
// effort limit (so that the saturating policies clamp now and then), further instances 0.2x,
// wrenches up to 2 N m / 20 N, alpha random unit directions, beta in [-3, 3].
#pragma once

#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "scene/scene.hpp"
#include "solver/flat_layout.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::bench {

// Number of prepared states every benchmark cycles through.
constexpr std::size_t kStates = 64;
constexpr unsigned kSeed = 20240601;

struct SceneInputs {
  scene::Scene scene;
  model::Chain chain;
  std::size_t dof = 0, constraints = 0;
  std::vector<solver::SolveInputs<double>> problems;  // kStates random problems
  std::vector<std::vector<double>> flat;              // the same, as flat inputs
  std::vector<std::vector<double>> new_beta;          // kStates other setpoints (Nc each), for re-solves
};

// Loads the scene and its chain, and draws `count` random problems.
SceneInputs make_inputs(const std::string& scene_path, std::size_t count = kStates, unsigned seed = kSeed);

// Uniform random numbers; positions within joint limits ([-pi, pi] where unlimited).
class Random {
 public:
  explicit Random(unsigned seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  // A random unit 6-vector (moment and force parts sharing the unit norm).
  spatial::Force<double> unit_direction();

 private:
  std::mt19937_64 rng_;
};

}  // namespace sweepgen::bench
