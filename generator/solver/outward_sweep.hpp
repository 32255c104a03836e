// Outward sweep, base to tip (docs/derivation.md, section 2): X_i (F2), then, λ(i) the parent,
//   Ẍ_0 (O4), Ẋ_i  = X_i Ẋ_λ(i) + S_i q̇_i (O1),   Ẍb_i = Ẋ_i × (S_i q̇_i) (O2),   Fb_i = Ẋ_i ×* (M_i Ẋ_i) (O3).
// External forces are not folded into Fb here: every track adds its own (decomposition_sweep).
#pragma once

#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// @pre q, qd have N entries (a floating base's six are read from qd only); kin.body has N + 1.
// `base_rotation` (world_R_base, base coordinates -> world) is read for a floating base only.
template <class Scalar>
void outward_sweep_base_to_tip(const SolverModel<Scalar>& model, const JointVector<Scalar>& q,
                               const JointVector<Scalar>& qd, KinematicsState<Scalar>& kin,
                               const Mat3<Scalar>& base_rotation = Mat3<Scalar>::Identity()) {
  kin.base_acceleration = {};  // (O4)
  kin.base_acceleration.linear = model.floating_base ? Vec3<Scalar>(-(base_rotation.transpose() * model.gravity))
                                                     : Vec3<Scalar>(-model.gravity);
  for (std::size_t i = 1; i <= model.dof(); ++i) {
    const JointModel<Scalar>& joint = model.joints[i];
    BodyKinematics<Scalar>& body = kin.body[i];
    body.X = joint.transform(q[i - 1]);
    const spatial::Motion<Scalar> joint_velocity = joint.S * qd[i - 1];
    body.velocity = body.X.apply(kin.body[model.parent[i]].velocity) + joint_velocity;
    // (O2); zero for a floating base's coordinates: together one free joint, S = 1, Ẋ × Ẋ = 0 (F5)
    if (!joint.floating_base_coordinate) body.bias_acceleration = spatial::cross_motion(body.velocity, joint_velocity);
    body.bias_force = spatial::cross_force(body.velocity, model.inertia[i] * body.velocity);
  }
}

}  // namespace sweepgen::solver
