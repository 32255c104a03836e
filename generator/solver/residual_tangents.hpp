// The Jacobians along q and q̇ through the residuals of the solve's equations
// (docs/derivation.md, (D5)): at fixed q and q̇ the solution is linear in τff and β, so a change
// of q or q̇ acts on it like the change of τff and β that keeps its equations balanced. With
// the solution (q̈, ν) held fixed,
//   ρ = τff + Σ_k J_kᵀ (α_k ν_k) − (RNEA(q, q̇, q̈; F_ext) + d q̈)   (T1 − T2: the joints' torque balance)
//   r_k = E_cstr,k − α_kᵀ Ẍ_link(k)                              ((R1)'s residual: the constraints)
// and y = q̈ or ν: ∂y/∂x = ∂y/∂τff ∂ρ/∂x + ∂y/∂β ∂r/∂x for x = q, q̇.                    (D5)
// The τff and β columns come from the factored sweeps without any tangent of the kinematics;
// ∂ρ/∂x and ∂r/∂x come in closed form (residual_jacobians.hpp, (D8)): no tangent at all.
#pragma once

#include "solver/commanded_torque.hpp"
#include "solver/derivative_seeds.hpp"
#include "solver/residual_jacobians.hpp"

namespace sweepgen::solver {

// Whether (D5) gives the derivative of the solution returned: a solution of the equations ρ = 0,
// r = 0 (with the directions the pivoted factorisation keeps and the joints not locked: those
// it drops or locks have zero ∂y/∂β or ∂y/∂τff columns, so their residuals do not enter).
// `original` with the pivoted factorisation, and every policy without constraints (no r, no
// factorisation); with constraints, `prioritize_external` leaves r ≠ 0 by design and the damped
// factorisation (C3) is biased, so those are differentiated through every sweep (D1).
template <class Scalar>
bool differentiates_by_residuals(const SolverModel<Scalar>& model, Policy policy) {
  return model.constraints() == 0 ||
         (policy == Policy::original && model.constraint_factorisation == ConstraintFactorisation::pivoted_ldlt);
}

// The value of every entry, without tangent: what the sweeps of the τff and β columns read.
template <class T, class Matrix>
Matrix values_of(const Matrix& x) {
  Matrix v = x;
  for (Eigen::Index i = 0; i < x.size(); ++i) v.data()[i] = Dual<T>(x.data()[i].value());
  return v;
}

// y's tangent with its q and q̇ columns from (D5): ∂y/∂τff ∂ρ/∂x + ∂y/∂β ∂r/∂x.
template <class T>
Dual<T> through_residuals(const Dual<T>& y, const ResidualJacobians<Dual<T>>& residuals, const DerivativeColumns& columns) {
  typename Dual<T>::Tangent tangent(columns.count(), T(0));
  for (std::size_t c = 0; c < columns.count(); ++c) tangent[c] = y.derivative(c);
  const auto index = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
  for (std::size_t x = 0; x < columns.dof; ++x)
    for (const bool velocity : {false, true}) {
      if (columns.is_coupled(x)) continue;  // its columns are its source's (D8)
      const auto& rho = velocity ? residuals.rho_qd : residuals.rho_q;
      const auto& r = velocity ? residuals.r_qd : residuals.r_q;
      T sum(0);
      for (std::size_t j = 0; j < columns.dof; ++j)
        sum = sum + y.derivative(columns.tau_ff(j)) * rho(index(j), index(x)).value();
      for (std::size_t k = 0; k < columns.constraints; ++k)
        sum = sum + y.derivative(columns.beta(k)) * r(index(k), index(x)).value();
      tangent[velocity ? columns.qd(columns.independent(x)) : columns.q(columns.independent(x))] = sum;
    }
  return Dual<T>(y.value(), std::move(tangent));
}

// (D5): `sol` solved with tangents along τff and β only, from `kin_values` (the outward sweep of
// q, q̇ without tangent; `qd_values` its q̇). Completes the q and q̇ columns of q̈ and ν with the
// residuals' Jacobians (D8), then τcmd (T1) from them with every column, which reads `kin`, the
// outward sweep seeded along (D2)'s columns. Returns (D8)'s quantities (values, no tangent).
template <class T>
ResidualJacobians<Dual<T>> complete_by_residuals(const SolverModel<Dual<T>>& model, const KinematicsState<Dual<T>>& kin_values,
                           const JointVector<Dual<T>>& qd_values, const KinematicsState<Dual<T>>& kin,
                           const DriverInputs<Dual<T>>& inputs, Solution<Dual<T>>& sol) {
  const auto columns = DerivativeColumns::of(model.dof(), model.set_directions(), model.couplings);
  Solution<Dual<T>> held = sol;  // (q̈, ν) held fixed: values only
  held.qdd = values_of<T>(sol.qdd);
  held.nu = values_of<T>(sol.nu);
  const ResidualJacobians<Dual<T>> residuals = residual_jacobians(model, kin_values, qd_values, inputs, held);
  for (Eigen::Index i = 0; i < sol.qdd.size(); ++i) sol.qdd[i] = through_residuals(sol.qdd[i], residuals, columns);
  for (Eigen::Index k = 0; k < sol.nu.size(); ++k) sol.nu[k] = through_residuals(sol.nu[k], residuals, columns);
  constraint_torque_tip_to_base(model, kin, inputs, sol);
  return residuals;
}

}  // namespace sweepgen::solver
