// Seeded random inputs for the benchmarks, in the flat input order of the generated code
// (the same recipe as tests/support/generated_check.hpp, kept separate so bench/ does not
// depend on the test helpers):
//   in = [q, qd, tau (per torque instance), wrench (per external force, [moment; force]),
//         alpha (Nc unit 6-vectors, only when the directions are run-time inputs), beta (Nc)]
// q within the joint limits, qd in [-2, 2] rad/s, the first torque instance up to 1.5x the
// effort limit (so that the saturating policies clamp now and then), further instances 0.2x,
// wrenches up to 2 N m / 20 N, alpha random unit directions, beta in [-3, 3].
#pragma once

#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::bench {

// Number of prepared states every benchmark cycles through.
constexpr std::size_t kStates = 64;
constexpr unsigned kSeed = 20240601;

struct SceneInputs {
  scene::Scene scene;
  model::Chain chain;
  std::size_t dof = 0, constraints = 0;
  std::vector<std::vector<double>> flat;      // kStates flat inputs (double)
  std::vector<std::vector<double>> new_beta;  // kStates other setpoints (Nc each), for re-solves
};

// Loads the scene and its chain, and draws `count` random flat inputs.
SceneInputs make_inputs(const std::string& scene_path, std::size_t count = kStates, unsigned seed = kSeed);

// The flat inputs as the reference solver's arguments.
struct ReferenceInput {
  solver::JointVector<double> q, qd;
  solver::DriverInputs<double> drivers;
  solver::ConstraintVector<double> beta;
};
std::vector<ReferenceInput> reference_inputs(const SceneInputs& inputs);

// Uniform random numbers; positions within joint limits ([-pi, pi] where unlimited).
class Random {
 public:
  explicit Random(unsigned seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  // A random unit 6-vector (moment and force parts sharing the unit norm), appended to `out`.
  void unit_direction(std::vector<double>& out);

 private:
  std::mt19937_64 rng_;
};

}  // namespace sweepgen::bench
