// The solution of one solve and its Jacobians (docs/derivation.md, (D1)–(D5)): ∂q̈, ∂ν and
// ∂τcmd with respect to q, q̇, τff and β, by running the reference sweeps with the dual scalar
// (dual_scalar.hpp) seeded along the input coordinates: every one, or, where (D5) applies
// (residual_tangents.hpp), τff and β through the solve and q, q̇ through its equations'
// residuals. The equations are the solver's own; nothing here restates them.
//
// Coordinates (D2), the columns of each Jacobian:
//   q   nv columns: the joints' positions but the coupled <mimic> joints' (M1: theirs follow their
//       sources', whose columns hold the whole derivative); a floating base's six leading columns
//       are its tangent coordinates [δθ; δp], δθ the body-frame rotation vector of world_R_base
//       (world_R_base exp([δθ]×)), δp its position, which nothing depends on (zero columns);
//   q̇   nv columns (a floating base's twist [ω; v] first);
//   τff dof columns, a joint torque added to every torque driver's sum (seeded on the first
//       instance: the instances enter every policy as one sum);
//   β   Nc columns, the sets' directions (a coupling's setpoint is 0, not an input).
// Rows: q̈ and τcmd every joint's, ν the sets' directions (not the couplings' torques).
// Policies: original and prioritize_external. The saturating ones are refused (their clamp is
// a kink of the solution: no derivative there, and a one-sided one elsewhere).
// Where the factorisation drops a direction or a joint is locked (J1), the derivative is that of
// the solution returned (the dropped multiplier and the locked q̈_i stay 0), and `status` says so.
#pragma once

#include <stdexcept>
#include <string>

#include "solver/derivative_seeds.hpp"
#include "solver/reference_solver.hpp"
#include "solver/residual_tangents.hpp"

namespace sweepgen::solver {

template <class Scalar>
using JacobianMatrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

// ∂y/∂(q, q̇, τff, β) of one output y, rows y's entries (D2).
template <class Scalar>
struct Jacobians {
  JacobianMatrix<Scalar> q, qd, tau_ff, beta;
};

template <class Scalar>
struct SolveDerivatives {
  JointVector<Scalar> qdd, tau_cmd;
  ConstraintVector<Scalar> nu;
  unsigned status = status_ok;
  Jacobians<Scalar> d_qdd, d_nu, d_tau_cmd;
};

template <class Scalar>
class DerivativeSolver {
 public:
  using D = Dual<Scalar>;

  // Throws std::invalid_argument when the layout has no torque driver (no τff to differentiate by).
  DerivativeSolver(const model::Chain& chain, const DriverLayout& layout, const SolverOptions& options = {})
      : solver_(chain, layout, options) {
    if (layout.torques.empty())
      throw std::invalid_argument("derivatives need a feed-forward torque driver (the columns of d/d tau_ff)");
  }

  std::size_t dof() const { return solver_.dof(); }
  std::size_t constraints() const { return solver_.model().set_directions(); }

  // The solve of `in` under `policy` and its Jacobians. Throws std::invalid_argument for a
  // saturating policy.
  SolveDerivatives<Scalar> solve(const SolveInputs<Scalar>& in, Policy policy);

 private:
  DerivativeColumns columns() const { return DerivativeColumns::of(dof(), constraints(), solver_.model().couplings); }

  // Values and the four column blocks of the tangents (D2's order: q, q̇, τff, β).
  template <class In, class Out>
  void split(const In& y, Out& value, Jacobians<Scalar>& d) const {
    const DerivativeColumns columns = this->columns();
    const Eigen::Index rows = y.size();
    const auto size = [](std::size_t s) { return static_cast<Eigen::Index>(s); };
    value.resize(rows);
    for (auto* block : {&d.q, &d.qd}) block->resize(rows, size(columns.velocities()));
    d.tau_ff.resize(rows, size(columns.dof));
    d.beta.resize(rows, size(columns.constraints));
    for (Eigen::Index r = 0; r < rows; ++r) {
      value[r] = y[r].value();
      for (std::size_t j = 0; j < columns.velocities(); ++j) {
        d.q(r, size(j)) = y[r].derivative(columns.q(j));
        d.qd(r, size(j)) = y[r].derivative(columns.qd(j));
      }
      for (std::size_t j = 0; j < columns.dof; ++j) d.tau_ff(r, size(j)) = y[r].derivative(columns.tau_ff(j));
      for (std::size_t k = 0; k < columns.constraints; ++k)
        d.beta(r, static_cast<Eigen::Index>(k)) = y[r].derivative(columns.beta(k));
    }
  }

  ReferenceSolver<D> solver_;
};

// Outside the class, so that the explicit instantiation below compiles it once
// (reference_solver_dual.cpp) for every file that differentiates in double.
template <class Scalar>
SolveDerivatives<Scalar> DerivativeSolver<Scalar>::solve(const SolveInputs<Scalar>& in, Policy policy) {
  if (!differentiable(policy))
    throw std::invalid_argument(std::string("policy ") + name(policy) +
                                " has no derivative (its clamp is a kink); differentiable: original, prioritize_external");
  const std::size_t n = dof(), nc = constraints();
  const DerivativeColumns columns = this->columns();
  const SolverModel<D>& model = solver_.model();
  const std::size_t base = model.base_coordinates();
  const SeededKinematics<Scalar> seeds = seeded_kinematics(in.q, in.qd, in.base_rotation, base, columns);
  const JointVector<D>& q = seeds.q;
  const JointVector<D>& qd = seeds.qd;
  const Mat3<D>& rotation = seeds.base_rotation;
  // (D5): the sweeps read q, q̇ without tangent; the q and q̇ columns come from the residuals.
  const bool by_residuals = differentiates_by_residuals(model, policy);
  if (by_residuals)
    solver_.outward(values_of<Scalar>(q), values_of<Scalar>(qd), values_of<Scalar>(rotation));
  else
    solver_.outward(q, qd, rotation);
  auto& drivers = solver_.drivers();
  for (std::size_t t = 0; t < in.torques.size(); ++t) drivers.torques[t] = in.torques[t].template cast<D>();
  for (std::size_t i = 0; i < n; ++i) drivers.torques[0][i] = seeded(in.torques[0][i], columns.tau_ff(i), columns);
  const auto force = [](const spatial::Force<Scalar>& f) {
    return spatial::Force<D>{f.moment.template cast<D>(), f.force.template cast<D>()};
  };
  for (std::size_t e = 0; e < in.wrenches.size(); ++e) drivers.external_forces[e] = force(in.wrenches[e]);
  for (std::size_t k = 0; k < in.alpha.size(); ++k) drivers.constraint_directions[k] = force(in.alpha[k]);
  solver_.decompose();
  ConstraintVector<D> beta(nc);
  for (std::size_t k = 0; k < nc; ++k) beta[k] = seeded(in.beta[k], columns.beta(k), columns);
  Solution<D> s = solver_.solve(policy, beta);
  mirror_symmetric_columns(s.qdd, s.nu, columns);  // (D7)
  if (by_residuals) {
    auto kin = KinematicsState<D>::sized(n);
    outward_sweep_base_to_tip(model, q, qd, kin, rotation);
    complete_by_residuals(model, solver_.kinematics(), values_of<Scalar>(qd), kin, drivers, s);
  }

  SolveDerivatives<Scalar> out;
  out.status = solver_.status();
  split(s.qdd, out.qdd, out.d_qdd);
  split(s.tau_cmd, out.tau_cmd, out.d_tau_cmd);
  split(ConstraintVector<D>(s.nu.head(static_cast<Eigen::Index>(nc))), out.nu, out.d_nu);
  return out;
}

extern template class ReferenceSolver<Dual<double>>;
extern template class DerivativeSolver<double>;

}  // namespace sweepgen::solver
