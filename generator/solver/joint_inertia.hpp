// The joint-space articulated inertia D_i = d_i + S_i^T M^A_i S_i (docs/derivation.md, (I0)) and
// the scale the joint-inertia policy (J1) judges it against (docs/stability.md, "Joint-space
// inertia D_i").
//
// D_i is the inertia the outboard articulated body shows through joint i. Rounding perturbs
// it by about eps times the size of the entries of M^A_i it is read from, so its relative
// accuracy is eps / ρ_i with
//     ρ_i = D_i / (d_i + tr A^A_i)   revolute joint  (A^A_i: rotational block about the body origin, kg m²)
//     ρ_i = D_i / (d_i + tr C^A_i)   prismatic joint (C^A_i: translational block, kg)
// 0 <= ρ_i <= 1 (S_i is a unit axis and the blocks are positive semi-definite). ρ_i has no
// units: scaling lengths and masses by any factors leaves it unchanged, so a rule on ρ_i
// makes the same decision for a robot in any units.
#pragma once

#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// d_i + tr of the block of M^A_i that S_i reads.
template <class Scalar>
Scalar joint_inertia_scale(const JointModel<Scalar>& joint, const spatial::Inertia<Scalar>& articulated) {
  const Mat3<Scalar>& block = joint.type == model::JointType::revolute ? articulated.A : articulated.C;
  return joint.rotor_inertia + block(0, 0) + block(1, 1) + block(2, 2);
}

// (J2): where d_i = 0 and joint i never locks, S_i^T (F − U_i D_i^-1 S_i^T F) = S_i^T F (1 − S_i^T U_i / D_i)
// = 0 for every F, and S_i^T (F + U_i D_i^-1 (τ − S_i^T F)) = τ. With S_i = ±e_k the k-th component
// of the projected force is set to those values exactly (`value` 0 or ±τ), and row and column k
// of the projected inertia M^A_i − U_i D_i^-1 U_i^T to 0: the rounding they would carry goes, and
// the symbolic scalar sees literal zeros that fold through the transforms to the parent.
template <class Scalar>
void set_axis_component(const JointModel<Scalar>& joint, spatial::Force<Scalar>& f, const Scalar& value) {
  if (joint.exact_zero_component < 0) return;
  Vec3<Scalar>& part = joint.type == model::JointType::revolute ? f.moment : f.force;
  part[joint.exact_zero_component] = value;
}

// S_i^T F' = τ for the force handed on: F' = F + U_i D_i^-1 (τ − S_i^T F), S_i = ±e_k: F'_k = ±τ.
template <class Scalar>
void set_axis_component_to_torque(const JointModel<Scalar>& joint, spatial::Force<Scalar>& f, const Scalar& tau) {
  if (joint.exact_zero_component < 0) return;
  set_axis_component(joint, f, joint.axis[joint.exact_zero_component] * tau);
}

template <class Scalar>
void zero_axis_row_and_column(const JointModel<Scalar>& joint, spatial::Inertia<Scalar>& projected) {
  const int k = joint.exact_zero_component;
  if (k < 0) return;
  if (joint.type == model::JointType::revolute) {  // column k of [A; B^T]: A's row and column, B's row
    projected.A.row(k).setZero();
    projected.A.col(k).setZero();
    projected.B.row(k).setZero();
  } else {  // column k of [B; C]
    projected.C.row(k).setZero();
    projected.C.col(k).setZero();
    projected.B.col(k).setZero();
  }
}

// ρ_i = D_i / (d_i + tr block), 0 where the scale is 0 (nothing moves through the joint).
// For measurements; the solver's rule compares without dividing.
template <class Scalar>
Scalar relative_joint_inertia(const JointModel<Scalar>& joint, const BodyArticulated<Scalar>& body) {
  const Scalar scale = joint_inertia_scale(joint, body.articulated_inertia);
  return scale > Scalar(0) ? body.D / scale : Scalar(0);
}

// min_i ρ_i over the chain's joints (1 for none): the worst amplification 1 / ρ_i of rounding in
// q̈ (docs/stability.md, κ).
template <class Scalar>
Scalar min_relative_joint_inertia(const SolverModel<Scalar>& model, const ArticulatedState<Scalar>& art) {
  Scalar smallest(1);
  for (std::size_t i = 1; i <= model.dof(); ++i) {
    const Scalar rho = relative_joint_inertia(model.joints[i], art.body[i]);
    if (rho < smallest) smallest = rho;
  }
  return smallest;
}

}  // namespace sweepgen::solver
