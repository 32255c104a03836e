// The dense KKT solve (`sweepgen report`'s "dense KKT" row, bench_calls, the tests): the textbook
// alternative to a recursive solver. M(q),
// b(q, q̇) and the tip Jacobian from Newton–Euler (oracle/dense_dynamics.hpp, which shares no
// code with generator/solver), then the (n + Nc) saddle-point system of Gauss' principle,
//   [ M   −Jcᵀ ] [q̈]   [ τ + Σ J_iᵀ F_ext,i − b ]
//   [ Jc    0  ] [ν] = [ β − αᵀ c               ],   Jc = αᵀ J_tip,
// solved by Eigen's full-pivot LU, in double. It solves the original policy's problem with every
// direction kept: where the directions are dependent the system is singular and so is its answer
// (no pivot policy drops a direction).
#pragma once

#include <string>
#include <vector>

#include "oracle/dense_dynamics.hpp"
#include "scene/scene.hpp"
#include "solver/drivers.hpp"
#include "solver/solve_inputs.hpp"

namespace sweepgen::oracle {

// One problem posed for the dense KKT solve, as the report times it and bench_calls counts it:
// the oracle with this state's gravity (a floating base's turned by its base rotation, (O4)),
// τff summed over the torque instances, the wrenches on their links and α as columns.
struct DenseKktProblem {
  using Dynamics = DenseDynamics<double>;
  Dynamics dynamics;
  Eigen::VectorXd tau;
  std::vector<Dynamics::ExternalWrench> wrenches;
  Dynamics::Mat alpha;
  std::vector<std::string> links;  // per direction, its set's link

  DenseKktProblem(const scene::Scene& s, const model::Chain& chain, const solver::SolveInputs<double>& p)
      : dynamics(chain, chain.floating_base ? model::Vec3(p.base_rotation.transpose() * s.gravity) : s.gravity),
        tau(Eigen::VectorXd::Zero(p.q.size())),
        alpha(6, static_cast<Eigen::Index>(s.layout.constraints)),
        links(solver::direction_links(s.layout, chain)) {
    for (const auto& t : p.torques) tau += t;
    for (std::size_t e = 0; e < p.wrenches.size(); ++e) {
      Dynamics::Six w;
      w << p.wrenches[e].moment, p.wrenches[e].force;
      wrenches.push_back({s.layout.external_forces[e].link, w});
    }
    for (std::size_t k = 0; k < s.layout.constraints; ++k)
      alpha.col(static_cast<Eigen::Index>(k)) << p.alpha[k].moment, p.alpha[k].force;
  }

  // The dense solve of `p`, the problem this was posed from.
  Dynamics::KktSolution solve(const solver::SolveInputs<double>& p) const {
    return dynamics.solve_kkt(p.q, p.qd, tau, wrenches, links, alpha, p.beta);
  }
};

}  // namespace sweepgen::oracle
