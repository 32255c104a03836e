// Random problems posed identically to the reference solver (double) and to the dense oracle
// (long double): one torque instance, one or two external-force instances, Nc constraint
// directions, and the cases (bundled robots, random chains) the oracle tests run over.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "oracle/relative_error.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "oracle/dense_dynamics.hpp"
#include "support/random_chain.hpp"
#include "support/random_problem.hpp"

namespace sweepgen::test {

using LongDouble = long double;
using Oracle = oracle::DenseDynamics<LongDouble>;
using OracleVec = Oracle::Vec;
using OracleMat = Oracle::Mat;

// A chain and the links its external-force instances act on.
struct OracleCase {
  std::string name;
  model::Chain chain;
  std::vector<std::string> external_links;
};

// The bundled robots at their default tips (behind fixed joints), forces on the tip and on a
// middle link. With `rotor_inertia`, every other joint gets d_i = 0.1 (URDF has no armature).
inline std::vector<OracleCase> bundled_cases(bool rotor_inertia) {
  std::vector<OracleCase> cases;
  for (const auto& robot : bundled_robots()) {
    OracleCase c{robot.name, load_bundled(robot), {}};
    c.external_links = {c.chain.tip_link, c.chain.bodies[c.chain.dof() / 2 + 1].link};
    if (rotor_inertia)
      for (std::size_t i = 1; i <= c.chain.dof(); i += 2) c.chain.joints[i].rotor_inertia = 0.1;
    cases.push_back(c);
  }
  return cases;
}

// A random chain (or, with `tree`, a random tree; with `floating_tree`, one on a floating base) with one or two external forces on random
// moving links (lumped frames included).
inline OracleCase random_case(RandomChainGenerator& generator, bool tree = false, bool floating_tree = false) {
  OracleCase c{"", floating_tree ? generator.floating_tree() : tree ? generator.tree() : generator.chain(), {}};
  c.name = c.chain.source;
  std::vector<std::string> moving;
  for (const auto& [link, frame] : c.chain.frames)
    if (frame.body > 0) moving.push_back(link);
  const int count = generator.chance(0.5) ? 1 : 2;
  for (int k = 0; k < count; ++k)
    c.external_links.push_back(moving[static_cast<std::size_t>(generator.uniform(0, 1) * moving.size()) % moving.size()]);
  return c;
}

// Decomposed layout (Alg. 2): the bias, one torque instance and the external forces on tracks of their own.
inline solver::DriverLayout oracle_layout(const OracleCase& c, std::size_t nc) {
  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  for (std::size_t k = 0; k < c.external_links.size(); ++k)
    layout.external_forces.push_back({"ext" + std::to_string(k), c.external_links[k]});
  layout.constraints = nc;
  layout.decompose_all();
  return layout;
}

inline Oracle::Six to_six(const spatial::Force<double>& f) {
  Oracle::Six s;
  s << f.moment.cast<LongDouble>(), f.force.cast<LongDouble>();
  return s;
}
inline Oracle::Six to_six(const spatial::Motion<double>& m) {
  Oracle::Six s;
  s << m.angular.cast<LongDouble>(), m.linear.cast<LongDouble>();
  return s;
}
template <class Derived>
OracleVec to_long(const Eigen::MatrixBase<Derived>& v) {
  return v.template cast<LongDouble>();
}

// One random state and its drivers, in both precisions.
struct OracleProblem {
  Eigen::VectorXd q, qd, tau_ff;
  std::vector<spatial::Force<double>> wrenches;
  solver::ConstraintForces<double> alpha_columns{};
  solver::ConstraintVector<double> beta;
  model::Mat3 base_rotation = model::Mat3::Identity();  // world_R_base of a floating base (F5)

  // Gravity in the root link's frame: the oracle's fixed gravity (for a floating base, turned by
  // base_rotation).
  model::Vec3 base_gravity(const model::Vec3& gravity = model::Vec3(0, 0, -9.81)) const {
    return base_rotation.transpose() * gravity;
  }

  std::vector<Oracle::ExternalWrench> oracle_wrenches(const OracleCase& c) const {
    std::vector<Oracle::ExternalWrench> ext;
    for (std::size_t k = 0; k < wrenches.size(); ++k) ext.push_back({c.external_links[k], to_six(wrenches[k])});
    return ext;
  }
  OracleMat alpha(std::size_t nc) const {
    OracleMat a(6, nc);
    for (std::size_t k = 0; k < nc; ++k) a.col(k) = to_six(alpha_columns[k]);
    return a;
  }
};

// `torque_fraction`: τff up to that fraction of each joint's effort limit.
inline OracleProblem draw_problem(RandomProblem& random, const OracleCase& c, std::size_t nc,
                                  double torque_fraction = 0.5) {
  OracleProblem p;
  p.q = random.positions(c.chain);
  p.qd = random.velocities(c.chain);
  p.tau_ff = random.torques(c.chain, torque_fraction);
  for (std::size_t k = 0; k < c.external_links.size(); ++k) p.wrenches.push_back(random.wrench());
  for (std::size_t k = 0; k < nc; ++k) p.alpha_columns[k] = random.unit_direction();
  p.beta.resize(nc);
  for (std::size_t k = 0; k < nc; ++k) p.beta[k] = random.uniform(-1, 1);
  if (c.chain.floating_base) p.base_rotation = random.rotation();
  return p;
}

// Runs the reference solver on `p` (outward, decompose, solve).
inline const solver::Solution<double>& solve(solver::ReferenceSolver<double>& s, const OracleProblem& p,
                                             solver::Policy policy) {
  s.outward(p.q, p.qd, p.base_rotation);
  auto& d = s.drivers();
  d.torques[0] = p.tau_ff;
  for (std::size_t k = 0; k < p.wrenches.size(); ++k) d.external_forces[k] = p.wrenches[k];
  d.constraint_directions = p.alpha_columns;
  s.decompose();
  return s.solve(policy, p.beta);
}

// ‖a − b‖∞ / max(1, ‖b‖∞) (oracle/relative_error.hpp), in the oracles' precision.
template <class A, class B>
double relative_error(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return static_cast<double>(oracle::relative_error<LongDouble>(a.derived(), b.derived()));
}

}  // namespace sweepgen::test
