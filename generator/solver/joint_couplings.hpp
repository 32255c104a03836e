// Coupled <mimic> joints in the sweeps (docs/derivation.md, M1, M2): each coupling is one more
// constraint direction, numbered after the sets' (SolverModel::coupling_direction), with setpoint 0
// and no wrench: its unit force is the torque pair τ_c = e_m − k e_s (+1 on the mimic joint m, −k
// on its source s), which enters the rows r_i = S_i^T F^A_cstr,i + τ_c,i of (I2)/(I3) and (I6), the
// joint torques of (S3) through them, and (T1); its achieved acceleration is q̈_m − k q̈_s (R1).
// The mimic joint's q and q̇ are not inputs: q_m = k q_s + o, q̇_m = k q̇_s.
#pragma once

#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// q of joint i (1..N) as the sweeps take it: its input, or k q_s + o where it is coupled (M1).
template <class Scalar>
Scalar joint_position(const SolverModel<Scalar>& model, const JointVector<Scalar>& q, std::size_t i) {
  const int c = model.joints[i].coupling;
  if (c < 0) return q[static_cast<Eigen::Index>(i - 1)];
  const JointCouplingModel<Scalar>& coupling = model.couplings[static_cast<std::size_t>(c)];
  return coupling.multiplier * q[static_cast<Eigen::Index>(coupling.source - 1)] + coupling.offset;
}

// q̇ of joint i: its input, or k q̇_s where it is coupled (M1).
template <class Scalar>
Scalar joint_velocity(const SolverModel<Scalar>& model, const JointVector<Scalar>& qd, std::size_t i) {
  const int c = model.joints[i].coupling;
  if (c < 0) return qd[static_cast<Eigen::Index>(i - 1)];
  const JointCouplingModel<Scalar>& coupling = model.couplings[static_cast<std::size_t>(c)];
  return coupling.multiplier * qd[static_cast<Eigen::Index>(coupling.source - 1)];
}

// τ_c,i of direction k (M2): 1 at the mimic joint of coupling k, −k at its source, 0 elsewhere and
// for the sets' directions.
template <class Scalar>
Scalar coupling_torque_at(const SolverModel<Scalar>& model, std::size_t k, std::size_t i) {
  if (k < model.set_directions()) return Scalar(0);
  const JointCouplingModel<Scalar>& coupling = model.couplings[k - model.set_directions()];
  if (i == coupling.joint) return Scalar(1);
  if (i == coupling.source) return -coupling.multiplier;
  return Scalar(0);
}

// Whether direction k is a coupling with a torque on joint i.
template <class Scalar>
bool coupling_acts_at(const SolverModel<Scalar>& model, std::size_t k, std::size_t i) {
  if (k < model.set_directions()) return false;
  const JointCouplingModel<Scalar>& coupling = model.couplings[k - model.set_directions()];
  return i == coupling.joint || i == coupling.source;
}

// The setpoints of every direction: the sets' as given (Nc), then 0 for each coupling (M1).
// Without couplings the sets' own (solver_sweep.hpp takes them as they are, no copy).
template <class Scalar>
ConstraintVector<Scalar> with_coupling_setpoints(const SolverModel<Scalar>& model, const ConstraintVector<Scalar>& setpoints) {
  ConstraintVector<Scalar> all(model.constraints());
  for (std::size_t k = 0; k < model.constraints(); ++k)
    all[static_cast<Eigen::Index>(k)] = k < model.set_directions() ? setpoints[static_cast<Eigen::Index>(k)] : Scalar(0);
  return all;
}

}  // namespace sweepgen::solver
