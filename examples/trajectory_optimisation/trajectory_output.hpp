// The solved trajectory as a table, and its figure.
#pragma once

#include <string>
#include <vector>

#include "shooting_nlp.hpp"

namespace trajopt {

// Node k of the solution: time, state, the torque held over [t_k, t_{k+1}) (at k = N the last
// interval's, which closes the step plot), the hand's height over the plane and its normal
// velocity and q̇ᵀ∇²e q̇ (plane_dynamics.hpp, hand_height), and the plane's force ν at (x_k, τ).
struct Node {
  double t;
  double q[kDof], qd[kDof], tau[kDof];
  double height, height_rate, height_curvature, nu;
};
std::vector<Node> nodes_of(const Problem& problem, const std::vector<double>& x);

// OUT_DIR/trajectory.csv and OUT_DIR/trajectory.gp; runs gnuplot on the latter, which writes
// OUT_DIR/trajectory.png. False, with a message on stderr, where a file cannot be written or gnuplot fails.
bool write_trajectory(const std::string& out_dir, const std::vector<Node>& nodes);

}  // namespace trajopt
