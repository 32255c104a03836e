// The joint torques that realise the solved motion on a robot (docs/derivation.md, section 6,
// and "The traps"). Two inward passes of rigid force propagation, f_λ(i) += X_i^T f_i,
// τ_i = S_i^T f_i:
//   τcmd = τff + Σ_k J_k^T (α_k ν_k)          for the policies that keep the constraint;  (T1)
//          (J_k the Jacobian of direction k's link: its unit force enters at its body; for a set
//          between two links J_A − ^AX_B J_B, its pair of wrenches entering at both bodies, L4;
//          for a coupling its torque pair τ_c ν_k, M2)
//   τcmd = RNEA(q, q̇, q̈; F_ext) + d q̈         for any q̈ (used by Eq. 1 saturation).     (T2)
#pragma once

#include "solver/decomposition_sweep.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// Σ over torque instances of τff_i.
template <class Scalar>
Scalar feedforward_torque(const DriverInputs<Scalar>& inputs, std::size_t i) {
  Scalar tau(0);
  for (const auto& instance : inputs.torques) tau += instance[i - 1];
  return tau;
}

// τcmd = τff + Σ_k J_k^T (α_k ν_k)
template <class Scalar>
void constraint_torque_tip_to_base(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                   const DriverInputs<Scalar>& inputs, Solution<Scalar>& sol) {
  const std::size_t n = model.dof();
  // f_i: the constraint wrenches α_k ν_k on body i and the bodies beyond it, in body i's frame.
  for (auto& f : sol.transmitted_force) f = spatial::Force<Scalar>{};
  for (std::size_t i = n; i >= 1; --i) {
    spatial::Force<Scalar>& f = sol.transmitted_force[i];
    for (std::size_t k = 0; k < model.constraints(); ++k)
      if (constraint_enters_at(model, k, i)) f += constraint_own_force(model, kin, inputs, k, i) * sol.nu[k];
    sol.tau_cmd[i - 1] = feedforward_torque(inputs, i) + spatial::dot(f, model.joints[i].S);
    for (std::size_t k = model.set_directions(); k < model.constraints(); ++k)  // τ_c ν_k (M2)
      if (coupling_acts_at(model, k, i)) sol.tau_cmd[i - 1] += coupling_torque_at(model, k, i) * sol.nu[k];
    if (model.parent[i] > 0)
      sol.transmitted_force[model.parent[i]] = sol.transmitted_force[model.parent[i]] + kin.body[i].X.apply_transpose(f);
  }
}

// τcmd = RNEA(q, q̇, q̈; F_ext) + d q̈, from the accelerations Ẍ_i already in `sol`.
template <class Scalar>
void inverse_dynamics_torque_tip_to_base(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                         const DriverInputs<Scalar>& inputs, Solution<Scalar>& sol) {
  const std::size_t n = model.dof();
  // f_i: the net force body i and the bodies beyond it need, in body i's frame.
  for (auto& f : sol.transmitted_force) f = spatial::Force<Scalar>{};
  for (std::size_t i = n; i >= 1; --i) {
    spatial::Force<Scalar>& f = sol.transmitted_force[i];
    f += model.inertia[i] * sol.acceleration[i] + kin.body[i].bias_force;
    for (std::size_t k = 0; k < model.external_force_body.size(); ++k) f -= external_own_force(model, inputs, k, i);
    sol.tau_cmd[i - 1] = spatial::dot(f, model.joints[i].S) + model.joints[i].rotor_inertia * sol.qdd[i - 1];
    if (model.parent[i] > 0)
      sol.transmitted_force[model.parent[i]] = sol.transmitted_force[model.parent[i]] + kin.body[i].X.apply_transpose(f);
  }
}

}  // namespace sweepgen::solver
