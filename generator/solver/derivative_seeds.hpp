// The columns of the solve's Jacobians and the dual scalar's seeds along them (docs/derivation.md,
// (D2)), shared by the reference derivatives (solve_derivatives.hpp) and the trace the generated
// derivatives come from (symbolic/trace_derivatives.cpp): one numbering, one seeding.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "solver/dual_scalar.hpp"
#include "solver/joint_transform_tangent.hpp"  // Transform<Dual<T>> (D6), seen before any use
#include "solver/state.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::solver {

// (D2): q (nv), q̇ (nv), τff (dof), β (Nc), in this order. nv counts the joints but the coupled
// <mimic> ones (M1: their q and q̇ are their sources', no input of their own), so the q and q̇ columns
// are the generated code's inputs; Nc the sets' directions (a coupling's setpoint is 0, no input).
struct DerivativeColumns {
  std::size_t dof = 0, constraints = 0;
  std::vector<bool> coupled;  // per joint (0-based), whether it is a coupled <mimic> joint; empty: none

  // `couplings`: the coupled joints (each with `joint`, 1-based), as model::Chain or SolverModel holds them.
  template <class Couplings>
  static DerivativeColumns of(std::size_t dof, std::size_t constraints, const Couplings& couplings) {
    DerivativeColumns columns{dof, constraints, {}};
    if (!couplings.empty()) columns.coupled.assign(dof, false);
    for (const auto& c : couplings) columns.coupled[c.joint - 1] = true;
    return columns;
  }

  bool is_coupled(std::size_t joint) const { return !coupled.empty() && coupled[joint]; }
  std::size_t velocities() const {
    return dof - static_cast<std::size_t>(std::count(coupled.begin(), coupled.end(), true));
  }
  // Joint `joint`'s (0-based, not coupled) place among the q and q̇ columns, and the joint of a place.
  std::size_t independent(std::size_t joint) const {
    std::size_t place = 0;
    for (std::size_t j = 0; j < joint; ++j) place += is_coupled(j) ? 0 : 1;
    return place;
  }
  std::size_t joint_of(std::size_t place) const {
    std::size_t joint = 0;
    for (std::size_t seen = 0;; ++joint)
      if (!is_coupled(joint) && seen++ == place) return joint;
  }

  std::size_t count() const { return 2 * velocities() + dof + constraints; }
  std::size_t q(std::size_t place) const { return place; }
  std::size_t qd(std::size_t place) const { return velocities() + place; }
  std::size_t tau_ff(std::size_t i) const { return 2 * velocities() + i; }
  std::size_t beta(std::size_t k) const { return 2 * velocities() + dof + k; }
};

// The outputs of the solve whose Jacobians a derivatives_<policy> function returns (scene key
// derivatives: true for all three, or a list of them). The values q̈, ν, τcmd are returned always.
struct DerivativeOutputs {
  bool qdd = true, nu = true, tau_cmd = true;

  // Values in a derivatives_<policy>_flat output: q̈ (dof), ν (Nc), τcmd (dof), then the Jacobians
  // returned (rows of count() columns) in the same order, then the status.
  std::size_t flat_out_size(const DerivativeColumns& columns) const {
    const std::size_t rows = (qdd ? columns.dof : 0) + (nu ? columns.constraints : 0) + (tau_cmd ? columns.dof : 0);
    return 2 * columns.dof + columns.constraints + rows * columns.count() + 1;
  }
};

// (D7): the constrained solve's Jacobians along τff and β come from one symmetric matrix,
//   [∂q̈/∂τff  ∂q̈/∂β]   [ M⁻¹ − M⁻¹Jᵀ E⁻¹ J M⁻¹   M⁻¹Jᵀ E⁻¹ ]
//   [∂ν/∂τff  ∂ν/∂β ] = [ −E⁻¹ J M⁻¹               E⁻¹       ]  (E = J M⁻¹ Jᵀ; docs/derivation.md),
// so ∂q̈/∂τff is symmetric and ∂q̈/∂β = −(∂ν/∂τff)ᵀ. q̈'s entries below the diagonal of its τff
// block are taken from above it (row i, column τff(j < i): q̈_j's derivative along τff(i)), and
// its β columns from ν's τff columns: no tangent of an acceleration past body j along τff(j), nor
// any along β, is then read, and what is not read is not computed (the trace keeps what its
// outputs need). Applied to the solver sweep's q̈ and ν, before (D5) reads them.
template <class T>
void mirror_symmetric_columns(JointVector<Dual<T>>& qdd, const ConstraintVector<Dual<T>>& nu,
                              const DerivativeColumns& columns) {
  for (std::size_t i = 0; i < columns.dof; ++i) {
    typename Dual<T>::Tangent tangent(columns.count(), T(0));
    for (std::size_t c = 0; c < columns.count(); ++c) tangent[c] = qdd[i].derivative(c);
    for (std::size_t j = 0; j < i; ++j) tangent[columns.tau_ff(j)] = qdd[j].derivative(columns.tau_ff(i));
    for (std::size_t k = 0; k < columns.constraints; ++k) tangent[columns.beta(k)] = -nu[k].derivative(columns.tau_ff(i));
    qdd[i] = Dual<T>(qdd[i].value(), std::move(tangent));
  }
}

// `value` with tangent e_column (of `columns.count()` entries).
template <class T>
Dual<T> seeded(const T& value, std::size_t column, const DerivativeColumns& columns) {
  typename Dual<T>::Tangent tangent(columns.count(), T(0));
  tangent[column] = T(1);
  return Dual<T>(value, std::move(tangent));
}

// world_R_base exp([δθ]×) at δθ = 0, δθ the first three q columns (a floating base's rotation
// vector in its own frame): ∂R/∂δθ_k = R [e_k]×.
template <class T>
spatial::Mat3<Dual<T>> seeded_base_rotation(const spatial::Mat3<T>& R, const DerivativeColumns& columns) {
  spatial::Mat3<Dual<T>> seeded_R;
  for (Eigen::Index r = 0; r < 3; ++r)
    for (Eigen::Index c = 0; c < 3; ++c) {
      typename Dual<T>::Tangent tangent(columns.count(), T(0));
      for (Eigen::Index k = 0; k < 3; ++k) {
        const spatial::Mat3<T> K = spatial::skew(spatial::Vec3<T>(spatial::Vec3<T>::Unit(k)));
        T sum(0);
        for (Eigen::Index l = 0; l < 3; ++l) sum = sum + R(r, l) * K(l, c);
        tangent[columns.q(static_cast<std::size_t>(k))] = sum;
      }
      seeded_R(r, c) = Dual<T>(R(r, c), std::move(tangent));
    }
  return seeded_R;
}

// The outward sweep's inputs seeded along (D2)'s columns: q (a coupled joint's not seeded, nor a
// floating base's six: its q columns are world_R_base's rotation vector and its position), q̇ (a
// coupled joint's not seeded), and world_R_base (seeded for a floating base, `base` = 6; read as a
// constant otherwise).
template <class T>
struct SeededKinematics {
  JointVector<Dual<T>> q, qd;
  spatial::Mat3<Dual<T>> base_rotation;
};
template <class T>
SeededKinematics<T> seeded_kinematics(const JointVector<T>& q, const JointVector<T>& qd, const spatial::Mat3<T>& base_rotation,
                                      std::size_t base, const DerivativeColumns& columns) {
  using D = Dual<T>;
  SeededKinematics<T> out{JointVector<D>(q.size()), JointVector<D>(qd.size()),
                          base > 0 ? seeded_base_rotation(base_rotation, columns)
                                   : spatial::Mat3<D>(base_rotation.template cast<D>())};
  for (std::size_t i = 0; i < columns.dof; ++i) {
    const auto e = static_cast<Eigen::Index>(i);
    if (columns.is_coupled(i)) {  // read from its source's (joint_couplings.hpp): no column of its own
      out.q[e] = D(q[e]);
      out.qd[e] = D(qd[e]);
      continue;
    }
    const std::size_t place = columns.independent(i);
    out.q[e] = i < base ? D(q[e]) : seeded(q[e], columns.q(place), columns);
    out.qd[e] = seeded(qd[e], columns.qd(place), columns);
  }
  return out;
}

}  // namespace sweepgen::solver
