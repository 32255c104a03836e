// Solver sweeps, base to tip (docs/derivation.md, section 5): compose the tracks of the
// decomposition under a policy.
//   E_conf  = Σ_{t composed} E^A_t,0                                                    (S1)
//   ν       = (E^A_cstr,0)^-1 [E_cstr,N − F^A_cstr,0^T Ẍ_0 − E_conf]                     (S2)
//   τctrl_i = S_i^T F^A_cstr,i ν                           Alg. 3                        (S3)
//           + S_i^T Σ_{t external} (−F^A_t,i)               Alg. 4 adds the external forces
//           clamped to ±effort limit                        Eq. 1
//   q̈_i     = D_i^-1 (τff_i + τctrl_i − S_i^T (Σ_{t composed} F^A_t,i + M^A_i a_i)),   (S4)
//   a_i     = X_i Ẍ_λ(i) + Ẍb_i,       Ẍ_i = a_i + S_i q̈_i                              (S5)
// Refinement (original policy, pivoted factorisation): with r_k = E_cstr,k − α_kᵀ Ẍ_link(k) the
// residual of the first pass (for a coupling −(q̈_m − k q̈_s), M1), (S2)–(S5) once more with the
// setpoints E_cstr + r                                                                      (R1)
// and, for derivatives, ν differentiated as the first pass (its tangents need no refinement) (D4)
// Exact saturation clamps τcmd instead and runs forward dynamics with it: the extra torque
// Δτ = clamp(τcmd) − τff gets a track of its own (F^A_Δ, no constraint), by linearity (X1).
#pragma once

#include "solver/closure_error.hpp"
#include "solver/commanded_torque.hpp"
#include "solver/constraint_multipliers.hpp"
#include "solver/decomposition_sweep.hpp"
#include "solver/policy.hpp"

namespace sweepgen::solver {

// (ν): E_conf, ν and the number of dropped pivots.
template <class Scalar>
void constraint_multipliers(const SolverModel<Scalar>& model, const ArticulatedState<Scalar>& art,
                            const ConstraintVector<Scalar>& setpoints, Policy policy, Solution<Scalar>& sol) {
  const std::size_t nc = model.constraints();
  sol.conf_energy.setZero(nc);
  for (std::size_t t = 0; t < model.layout.tracks.size(); ++t)
    if (composes(model.layout.tracks[t], policy)) sol.conf_energy += art.track[t][0].acceleration_energy;
  ConstraintVector<Scalar> rhs(nc);
  for (std::size_t k = 0; k < nc; ++k)
    rhs[k] = setpoints[k] - art.base_acceleration_energy[k] - sol.conf_energy[k];
  BlockLowerBound<Scalar> lower_bound{art.private_energy, {}};  // (C5)
  for (std::size_t c = 0; c < model.private_top.size(); ++c)
    lower_bound.blocks.emplace_back(model.constraint_sets[c].first, model.constraint_sets[c].count);
  sol.nu = solve_constraint_multipliers(art.body[0].constraint_energy, rhs, model.constraint_factorisation,
                                        model.pivot_tolerance, sol.dropped_pivots, &sol.pivoted_path,
                                        model.private_top.empty() ? nullptr : &lower_bound);
}

// τctrl for the policies that keep the constraint (original, prioritize_external, saturate).
template <class Scalar>
void control_torques(const SolverModel<Scalar>& model, const ArticulatedState<Scalar>& art, Policy policy,
                     Solution<Scalar>& sol) {
  for (std::size_t i = 1; i <= model.dof(); ++i) {
    const JointModel<Scalar>& joint = model.joints[i];
    Scalar tau(0);
    for (std::size_t k = 0; k < model.constraints(); ++k) tau += art.body[i].constraint_row[k] * sol.nu[k];
    if (policy == Policy::prioritize_external) {
      spatial::Force<Scalar> f;
      for (std::size_t t = 0; t < model.layout.tracks.size(); ++t)
        if (model.layout.tracks[t].only_external_forces()) f -= art.track[t][i].articulated_force;
      tau += spatial::dot(f, joint.S);
    }
    sol.saturated[i - 1] = Scalar(0);
    if (policy == Policy::saturate) {
      sol.saturated[i - 1] = select_greater(abs_value(tau), joint.effort_limit, Scalar(1), Scalar(0));
      tau = clamp_symmetric(tau, joint.effort_limit);
    }
    sol.tau_ctrl[i - 1] = tau;
  }
}

// Ẍ of constraint set c's frame A, in its coordinates, from the accelerations Ẍ_i in `sol`; for a
// set between two links d/dt v_rel = Ẍ_A − ^AX_b Ẍ_b + v_A × ^AX_b Ẋ_b (L1).
template <class Scalar>
spatial::Motion<Scalar> set_acceleration(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                         const Solution<Scalar>& sol, std::size_t c) {
  const ConstraintSetModel<Scalar>& set = model.constraint_sets[c];
  const spatial::Motion<Scalar> at_A = set.frame.apply(sol.acceleration[set.body]);
  if (!set.relative) return at_A;
  return at_A - kin.loop[c].X_other.apply(sol.acceleration[set.other_body]) + kin.loop[c].velocity_product;
}

// a_i = X_i Ẍ_λ(i) + Ẍb_i, body i's acceleration before its own joint's (S4), from Ẍ_λ(i) in `sol`.
template <class Scalar>
spatial::Motion<Scalar> carried_acceleration(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                             const Solution<Scalar>& sol, std::size_t i) {
  return kin.body[i].X.apply(sol.acceleration[model.parent[i]]) + kin.body[i].bias_acceleration;
}

// Ẍ_tip and each listed set's Ẍ_link, from the Ẍ_i in `sol` (S5).
template <class Scalar>
void link_accelerations(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin, Solution<Scalar>& sol) {
  sol.tip_acceleration = model.tip.apply(sol.acceleration[model.dof()]);
  for (std::size_t c = 0; c < sol.set_acceleration.size(); ++c) sol.set_acceleration[c] = set_acceleration(model, kin, sol, c);
}

// (S5) for the q̈ in `sol`: Ẍ_i = a_i + S_i q̈_i, base to tip.
template <class Scalar>
void accelerations_of_motion(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin, Solution<Scalar>& sol) {
  sol.acceleration[0] = kin.base_acceleration;
  for (std::size_t i = 1; i <= model.dof(); ++i)
    sol.acceleration[i] = carried_acceleration(model, kin, sol, i) + model.joints[i].S * sol.qdd[i - 1];
  link_accelerations(model, kin, sol);
}

// (q̈): accelerations from τff + τctrl; `extra_force` (F^A_Δ) is added when given.
template <class Scalar>
void accelerations_base_to_tip(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                               const ArticulatedState<Scalar>& art, const DriverInputs<Scalar>& inputs, Policy policy,
                               const std::vector<spatial::Force<Scalar>>* extra_force, Solution<Scalar>& sol) {
  sol.acceleration[0] = kin.base_acceleration;
  for (std::size_t i = 1; i <= model.dof(); ++i) {
    const JointModel<Scalar>& joint = model.joints[i];
    const BodyArticulated<Scalar>& a = art.body[i];
    const spatial::Motion<Scalar> a_i = carried_acceleration(model, kin, sol, i);
    spatial::Force<Scalar> F = a.articulated_inertia * a_i;
    for (std::size_t t = 0; t < model.layout.tracks.size(); ++t)
      if (composes(model.layout.tracks[t], policy)) F += art.track[t][i].articulated_force;
    if (extra_force != nullptr) F += (*extra_force)[i];
    sol.qdd[i - 1] =
        a.inverse_D * (feedforward_torque(inputs, i) + sol.tau_ctrl[i - 1] - spatial::dot(F, joint.S));
    sol.acceleration[i] = a_i + joint.S * sol.qdd[i - 1];
  }
  link_accelerations(model, kin, sol);
}

// Exact saturation, after an original solve filled sol.tau_cmd: clamp it, hand the extra
// torque Δτ to a track of its own, and redo the accelerations without the constraint.
template <class Scalar>
void saturate_commanded_torque(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                               const ArticulatedState<Scalar>& art, const DriverInputs<Scalar>& inputs,
                               Solution<Scalar>& sol) {
  const std::size_t n = model.dof();
  for (std::size_t i = 1; i <= n; ++i) {
    const Scalar& limit = model.joints[i].effort_limit;
    sol.saturated[i - 1] = select_greater(abs_value(sol.tau_cmd[i - 1]), limit, Scalar(1), Scalar(0));
    sol.tau_cmd[i - 1] = clamp_symmetric(sol.tau_cmd[i - 1], limit);
    sol.tau_ctrl[i - 1] = sol.tau_cmd[i - 1] - feedforward_torque(inputs, i);
    sol.correction_force[i] = spatial::Force<Scalar>{};
  }
  for (std::size_t i = n; i >= 1; --i) {
    Scalar u;
    const spatial::Force<Scalar> handed_up = track_force_to_parent(
        model.joints[i], kin.body[i], art.body[i], sol.correction_force[i], sol.tau_ctrl[i - 1], u);
    if (model.parent[i] > 0) sol.correction_force[model.parent[i]] += handed_up;
  }
  // Forward dynamics: τff + Δτ applied, no constraint force, every real force acting.
  accelerations_base_to_tip(model, kin, art, inputs, Policy::original, &sol.correction_force, sol);
}

// Whether (R1) applies: a policy whose answer meets α_kᵀ Ẍ_link(k) = E_cstr,k exactly (the others
// leave a residual by design) and the pivoted factorisation (the damped one is biased on
// purpose; refining would undo its damping).
// `policy` as the caller names it (saturate_exact's constraint stage is original's).
inline bool refines(bool refinement, std::size_t constraints, Policy policy, ConstraintFactorisation factorisation) {
  return refinement && constraints > 0 && (policy == Policy::original || policy == Policy::saturate_exact) &&
         factorisation == ConstraintFactorisation::pivoted_ldlt;
}
template <class Scalar>
bool refines(const SolverModel<Scalar>& model, Policy constraint_policy) {
  return refines(model.refinement, model.constraints(), constraint_policy, model.constraint_factorisation);
}

// (R1): E_cstr + r (refined_setpoints) with r_k = E_cstr,k − α_kᵀ Ẍ_link(k) (constraint_residuals). ν comes from E^A_cstr,0, formed as a sum of
// products over the chain like the normal equations of the constraint Jacobian, so its rounding
// is amplified by cond(E) (the square of the Jacobian's); Ẍ_link comes from the sweeps of the
// motion itself, so r measures that error without forming E again, and ν + E^-1 r removes it to
// first order (docs/stability.md, "Refinement"). A dropped direction's r changes nothing: its
// column of L and its pivot are 0.
template <class Scalar>
ConstraintVector<Scalar> constraint_residuals(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                              const DriverInputs<Scalar>& inputs,
                                              const ConstraintVector<Scalar>& setpoints, const Solution<Scalar>& sol) {
  ConstraintVector<Scalar> r(model.constraints());
  for (std::size_t c = 0; c < model.constraint_sets.size(); ++c) {
    const spatial::Motion<Scalar> achieved = set_acceleration(model, kin, sol, c);
    const ConstraintSetModel<Scalar>& set = model.constraint_sets[c];
    for (std::size_t k = set.first; k < set.first + set.count; ++k)
      r[k] = setpoints[k] - spatial::dot(inputs.constraint_directions[k], achieved);
  }
  for (std::size_t c = 0; c < model.couplings.size(); ++c) {  // (M1): 0 − (q̈_m − k q̈_s)
    const JointCouplingModel<Scalar>& coupling = model.couplings[c];
    r[model.set_directions() + c] = coupling.multiplier * sol.qdd[coupling.source - 1] - sol.qdd[coupling.joint - 1];
  }
  return r;
}
template <class Scalar>
ConstraintVector<Scalar> refined_setpoints(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                           const DriverInputs<Scalar>& inputs,
                                           const ConstraintVector<Scalar>& setpoints, const Solution<Scalar>& sol) {
  const ConstraintVector<Scalar> r = constraint_residuals(model, kin, inputs, setpoints, sol);
  ConstraintVector<Scalar> refined(model.constraints());
  for (std::size_t k = 0; k < model.constraints(); ++k) refined[k] = setpoints[k] + r[k];
  return refined;
}

// @pre kin and art from the outward and decomposition sweeps of the same state and drivers;
// `set_setpoints` E_cstr of the sets' Nc directions (the couplings' are 0).
template <class Scalar>
void solver_sweep_base_to_tip(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                              const ArticulatedState<Scalar>& art, const DriverInputs<Scalar>& inputs,
                              const ConstraintVector<Scalar>& set_setpoints, Policy policy, Solution<Scalar>& sol) {
  const Policy constraint_policy = policy == Policy::saturate_exact ? Policy::original : policy;
  ConstraintVector<Scalar> with_couplings;  // (M1): the couplings' setpoints 0 after the sets'
  if (!model.couplings.empty()) with_couplings = with_coupling_setpoints(model, set_setpoints);
  const ConstraintVector<Scalar>& setpoints = model.couplings.empty() ? set_setpoints : with_couplings;
  sol.locked_joints = Scalar(0);
  for (std::size_t i = 1; i <= model.dof(); ++i) sol.locked_joints += art.body[i].locked;
  const std::vector<spatial::Force<Scalar>>* no_extra_force = nullptr;
  const auto motion = [&] {  // (S3)–(S5)
    control_torques(model, art, constraint_policy, sol);
    accelerations_base_to_tip(model, kin, art, inputs, constraint_policy, no_extra_force, sol);
  };
  constraint_multipliers(model, art, setpoints, constraint_policy, sol);  // (S2)
  motion();
  if (refines(model, constraint_policy)) {
    const ConstraintVector<Scalar> first_pass = sol.nu;
    constraint_multipliers(model, art, refined_setpoints(model, kin, inputs, setpoints, sol), constraint_policy, sol);
    for (std::size_t k = 0; k < model.constraints(); ++k) sol.nu[k] = refined_value(sol.nu[k], first_pass[k]);  // (D4)
    motion();
  }
  if (policy == Policy::saturate)
    inverse_dynamics_torque_tip_to_base(model, kin, inputs, sol);
  else
    constraint_torque_tip_to_base(model, kin, inputs, sol);
  if (policy == Policy::saturate_exact) saturate_commanded_torque(model, kin, art, inputs, sol);
  if (model.has_relative_sets()) closure_errors(model, kin, sol.closure_error);  // (L1), (L3)
}

}  // namespace sweepgen::solver
