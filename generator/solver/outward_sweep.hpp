// Outward sweep, base to tip (docs/derivation.md, section 2): X_i (F2), then, λ(i) the parent,
//   Ẍ_0 (O4), Ẋ_i  = X_i Ẋ_λ(i) + S_i q̇_i (O1),   Ẍb_i = Ẋ_i × (S_i q̇_i) (O2),   Fb_i = Ẋ_i ×* (M_i Ẋ_i) (O3),
// then for each set between two links ^AX_b, v_rel and v_A × ^AX_b Ẋ_b (L1).
// A coupled <mimic> joint takes q = k q_s + o, q̇ = k q̇_s of its source (M1), not its inputs.
// External forces are not folded into Fb here: every track adds its own (decomposition_sweep).
#pragma once

#include "solver/joint_couplings.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// ^iX_c: the motion transform from body c's coordinates to body i's, c on i's path to the base,
// composed down the path, X_i ⋯ X_(the child of c on it) (F1).
template <class Scalar>
Transform<Scalar> transform_from_ancestor(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                          std::size_t i, std::size_t c) {
  if (i == c) return {};
  Transform<Scalar> X = kin.body[i].X;
  for (std::size_t j = model.parent[i]; j != c; j = model.parent[j]) X = X * kin.body[j].X;
  return X;
}

// (L1) of each set between two links, after the bodies' transforms and velocities: ^AX_b through
// the bodies' nearest common ancestor c, ^AX_b = X_A ^aX_c (^bX_c)^-1, then v_rel and the
// velocity-product term v_A × ^AX_b Ẋ_b.
template <class Scalar>
void loop_kinematics(const SolverModel<Scalar>& model, KinematicsState<Scalar>& kin) {
  kin.loop.resize(model.constraint_sets.size());  // no allocation where sized so (KinematicsState::sized)
  for (std::size_t s = 0; s < model.constraint_sets.size(); ++s) {
    const ConstraintSetModel<Scalar>& set = model.constraint_sets[s];
    if (!set.relative) continue;
    const std::size_t c = set.common_ancestor;
    LoopKinematics<Scalar>& loop = kin.loop[s];
    loop.between_links = true;
    loop.X_other = set.frame * transform_from_ancestor(model, kin, set.body, c) *
                   spatial::inverse(transform_from_ancestor(model, kin, set.other_body, c));
    const spatial::Motion<Scalar> v_A = set.frame.apply(kin.body[set.body].velocity);
    const spatial::Motion<Scalar> v_B_in_A = loop.X_other.apply(kin.body[set.other_body].velocity);
    loop.relative_velocity = v_A - v_B_in_A;
    loop.velocity_product = spatial::cross_motion(v_A, v_B_in_A);
  }
}

// ᴬX_B of set s between two links, from the outward sweep's ᴬX_b: ᴬX_b (X_B)^-1, X_B body b -> B.
// Its E is R_A^T R_B and its r is R_B^T (p_A − p_B): the pose error (L3) is the rotation vector of
// E^T and E r.
template <class Scalar>
Transform<Scalar> relative_pose(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin, std::size_t s) {
  return kin.loop[s].X_other * spatial::inverse(model.constraint_sets[s].other_frame);
}

// @pre q, qd have N entries (a floating base's six are read from qd only, a coupled joint's from
// neither); kin.body has N + 1.
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
    body.X = joint.transform(joint_position(model, q, i));
    const spatial::Motion<Scalar> joint_velocity = joint.S * solver::joint_velocity(model, qd, i);
    body.velocity = body.X.apply(kin.body[model.parent[i]].velocity) + joint_velocity;
    // (O2); zero for a floating base's coordinates: together one free joint, S = 1, Ẋ × Ẋ = 0 (F5)
    if (!joint.floating_base_coordinate) body.bias_acceleration = spatial::cross_motion(body.velocity, joint_velocity);
    body.bias_force = spatial::cross_force(body.velocity, model.inertia[i] * body.velocity);
  }
  loop_kinematics(model, kin);
}

}  // namespace sweepgen::solver
