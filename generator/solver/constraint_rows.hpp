// The rows r_i = S_i^T F^A_cstr,i carried outward (docs/derivation.md, (I6)): what the inward
// sweep needs of the unit-force columns F^A_cstr,i is only these rows ((I3), the torque terms of
// (I5), (S3)) and the sum the bias and the base acceleration add to the acceleration energy. By
// (I2), column k at body i is (P_{i+1}^T X_{i+1}^T) ... (P_b^T X_b^T) X_link^T α_k for the set on
// body b, so with w_i = S_i, w_j = P_j X_j w_λ(j) on the path from i out to b:
//   r_i,k = α_k^T X_link w_b                                              (I6)
// (for a set between two links, also − α_k^T ^AX_b' w_b' at its other body b', L4)
// and with z_0 = Ẍ_0, z_j = P_j X_j z_λ(j) + Ẍb_j:
//   F^A_cstr,0^T Ẍ_0 + Σ_{i>=1} F^A_cstr,i^T Ẍb_i = α_k^T X_link z_b        (I6)
// Here P_j w = w − S_j D_j^-1 U_j^T w is (I0)'s projection acting on motions (its transpose acts on
// forces). A coupling's unit torque τ_c (M2) adds τ_c,i to r_i and, at each joint j beyond i,
// τ_c,j σ_j with σ_j = −D_j^-1 U_j^T X_j w_λ(j), the share of S_j in w_j; to the energy likewise
// with z in place of w. Each joint's vector goes out only as far as the constrained links beyond it: on the
// Panda's 6-D tip set that is n (n − 1) / 2 = 21 steps of one 6-vector against (I2)'s N Nc = 42.
#pragma once

#include "solver/joint_couplings.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// P_j X_j w: one step of (I6) through body j (its articulated quantities from the inward sweep);
// `removed` = D_j^-1 U_j^T X_j w, the multiple of S_j it takes away (σ_j = −removed).
template <class Scalar>
spatial::Motion<Scalar> project_outward(const JointModel<Scalar>& joint, const BodyKinematics<Scalar>& body,
                                        const BodyArticulated<Scalar>& art, const spatial::Motion<Scalar>& w,
                                        Scalar& removed) {
  const spatial::Motion<Scalar> moved = body.X.apply(w);
  removed = art.inverse_D * spatial::dot(art.U, moved);
  return moved - joint.S * removed;
}

// Adds τ_c,j,k σ_j = −τ_c,j,k · removed to out[k] for every coupling k with a torque on joint j (M2).
template <class Scalar>
void add_coupling_projections(const SolverModel<Scalar>& model, std::size_t j, const Scalar& removed,
                              ConstraintVector<Scalar>& out) {
  for (std::size_t k = model.set_directions(); k < model.constraints(); ++k)
    if (coupling_acts_at(model, k, j)) out[k] -= coupling_torque_at(model, k, j) * removed;
}

// Whether body j or a body beyond it carries a constraint set (the bodies (I6) must reach).
template <class Scalar>
std::vector<bool> bodies_reaching_a_set(const SolverModel<Scalar>& model) {
  std::vector<bool> reaches(model.dof() + 1, false);
  for (const ConstraintSetModel<Scalar>& set : model.constraint_sets) {
    reaches[set.body] = true;
    if (set.relative) reaches[set.other_body] = true;
  }
  for (const JointCouplingModel<Scalar>& coupling : model.couplings) reaches[coupling.joint] = reaches[coupling.source] = true;
  for (std::size_t j = model.dof(); j >= 1; --j)
    if (reaches[j]) reaches[model.parent[j]] = true;
  return reaches;
}

// Adds α_k^T X_link v to out[k] for every direction k of the sets on body b, and −α_k^T ^AX_b v for
// the sets between two links whose other link rides on b (L4).
template <class Scalar>
void add_set_projections(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                         const DriverInputs<Scalar>& inputs, std::size_t b, const spatial::Motion<Scalar>& v,
                         ConstraintVector<Scalar>& out) {
  for (std::size_t s = 0; s < model.constraint_sets.size(); ++s) {
    const ConstraintSetModel<Scalar>& set = model.constraint_sets[s];
    if (set.body == b) {
      const spatial::Motion<Scalar> at_link = set.frame.apply(v);
      for (std::size_t k = set.first; k < set.first + set.count; ++k)
        out[k] += spatial::dot(inputs.constraint_directions[k], at_link);
    }
    if (set.relative && set.other_body == b) {
      const spatial::Motion<Scalar> at_A = kin.loop[s].X_other.apply(v);
      for (std::size_t k = set.first; k < set.first + set.count; ++k)
        out[k] -= spatial::dot(inputs.constraint_directions[k], at_A);
    }
  }
}

// r_i (I6), once the inward sweep has formed U_j, D_j^-1 of every body beyond i.
template <class Scalar>
ConstraintVector<Scalar> constraint_row_outward(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                                const ArticulatedState<Scalar>& art, const DriverInputs<Scalar>& inputs,
                                                const std::vector<bool>& reaches, std::size_t i) {
  const std::size_t n = model.dof();
  ConstraintVector<Scalar> row = ConstraintVector<Scalar>::Zero(model.constraints());
  std::vector<spatial::Motion<Scalar>> w(n + 1);
  std::vector<bool> beyond_i(n + 1, false);
  w[i] = model.joints[i].S;
  beyond_i[i] = true;
  add_set_projections(model, kin, inputs, i, w[i], row);
  for (std::size_t k = model.set_directions(); k < model.constraints(); ++k)
    if (coupling_acts_at(model, k, i)) row[k] = coupling_torque_at(model, k, i);  // τ_c,i (M2)
  for (std::size_t j = i + 1; j <= n; ++j) {
    beyond_i[j] = beyond_i[model.parent[j]];
    if (!beyond_i[j] || !reaches[j]) continue;
    Scalar removed;
    w[j] = project_outward(model.joints[j], kin.body[j], art.body[j], w[model.parent[j]], removed);
    add_set_projections(model, kin, inputs, j, w[j], row);
    add_coupling_projections(model, j, removed, row);
  }
  return row;
}

// F^A_cstr,0^T Ẍ_0 + Σ_i F^A_cstr,i^T Ẍb_i by (I6)'s z recursion, after the inward sweep.
template <class Scalar>
ConstraintVector<Scalar> bias_energy_outward(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                             const ArticulatedState<Scalar>& art, const DriverInputs<Scalar>& inputs) {
  const std::size_t n = model.dof();
  const std::vector<bool> reaches = bodies_reaching_a_set(model);
  ConstraintVector<Scalar> energy = ConstraintVector<Scalar>::Zero(model.constraints());
  std::vector<spatial::Motion<Scalar>> z(n + 1);
  z[0] = kin.base_acceleration;
  add_set_projections(model, kin, inputs, 0, z[0], energy);
  for (std::size_t j = 1; j <= n; ++j) {
    if (!reaches[j]) continue;
    Scalar removed;
    z[j] = project_outward(model.joints[j], kin.body[j], art.body[j], z[model.parent[j]], removed) +
           kin.body[j].bias_acceleration;
    add_set_projections(model, kin, inputs, j, z[j], energy);
    add_coupling_projections(model, j, removed, energy);
  }
  return energy;
}

}  // namespace sweepgen::solver
