// Names every scalar of the sweep states, as (array, body, component, value). The generator
// uses it to name what it stores and to order the generated statements; tests use it to
// compare generated intermediates with the reference's. Arrays with a body index have one
// row per body 0..N (kBodyless otherwise); components follow the math's order: motion
// [angular; linear], force [moment; force], matrices row-major.
#pragma once

#include <string>

#include "solver/flat_layout.hpp"
#include "solver/policy.hpp"
#include "solver/residual_jacobians.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

constexpr int kBodyless = -1;

template <class Scalar, class Visit>
void visit_motion(Visit& visit, const std::string& array, int body, const spatial::Motion<Scalar>& m, int offset = 0) {
  for (int c = 0; c < 3; ++c) visit(array, body, offset + c, m.angular[c]);
  for (int c = 0; c < 3; ++c) visit(array, body, offset + 3 + c, m.linear[c]);
}

template <class Scalar, class Visit>
void visit_force(Visit& visit, const std::string& array, int body, const spatial::Force<Scalar>& f, int offset = 0) {
  for (int c = 0; c < 3; ++c) visit(array, body, offset + c, f.moment[c]);
  for (int c = 0; c < 3; ++c) visit(array, body, offset + 3 + c, f.force[c]);
}

template <class Matrix, class Visit>
void visit_matrix(Visit& visit, const std::string& array, int body, const Matrix& m, int offset = 0) {
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) visit(array, body, offset + static_cast<int>(r * m.cols() + c), m(r, c));
}

// Outward sweep: X_E, X_r, velocity, bias_acceleration, bias_force (bodies 1..N), then per set
// between two links ^AX_b, v_rel and the velocity-product term (L1).
template <class Scalar, class Visit>
void visit_fields(const KinematicsState<Scalar>& kin, Visit&& visit) {
  for (int i = 1; i < static_cast<int>(kin.body.size()); ++i) {
    const auto& b = kin.body[i];
    visit_matrix(visit, "X_E", i, b.X.E);
    visit_matrix(visit, "X_r", i, b.X.r);
    visit_motion(visit, "velocity", i, b.velocity);
    visit_motion(visit, "bias_acceleration", i, b.bias_acceleration);
    visit_force(visit, "bias_force", i, b.bias_force);
  }
  for (std::size_t s = 0; s < kin.loop.size(); ++s) {  // sets between two links, set s at [s * 12] or [s * 6]
    const auto& l = kin.loop[s];
    if (!l.between_links) continue;
    const int at = static_cast<int>(s);
    visit_matrix(visit, "loop_X_E", kBodyless, l.X_other.E, 9 * at);
    visit_matrix(visit, "loop_X_r", kBodyless, l.X_other.r, 3 * at);
    visit_motion(visit, "relative_velocity", kBodyless, l.relative_velocity, 6 * at);
    visit_motion(visit, "velocity_product", kBodyless, l.velocity_product, 6 * at);
  }
}

// Inward sweep, tip to base: per body the articulated inertia (A, B, C blocks), U, D, 1/D,
// the constraint forces and energies; then each track's force and energy.
template <class Scalar, class Visit>
void visit_fields(const ArticulatedState<Scalar>& art, const DriverLayout& layout, Visit&& visit) {
  const int n = static_cast<int>(art.body.size()) - 1;
  const int nc = static_cast<int>(layout.constraints);
  for (int i = n; i >= 0; --i) {
    const auto& b = art.body[i];
    if (i > 0) {
      visit_matrix(visit, "articulated_inertia", i, b.articulated_inertia.A, 0);
      visit_matrix(visit, "articulated_inertia", i, b.articulated_inertia.B, 9);
      visit_matrix(visit, "articulated_inertia", i, b.articulated_inertia.C, 18);
      visit_force(visit, "U", i, b.U);
      visit(std::string("D"), i, 0, b.D);
      visit(std::string("inverse_D"), i, 0, b.inverse_D);
      visit(std::string("locked"), i, 0, b.locked);
      for (int k = 0; k < nc; ++k) visit(std::string("constraint_row"), i, k, b.constraint_row[k]);
    }
    for (int k = 0; k < nc; ++k) visit_force(visit, "constraint_force", i, b.constraint_force[k], 6 * k);
    visit_matrix(visit, "constraint_energy", i, b.constraint_energy);
    for (std::size_t t = 0; t < layout.tracks.size(); ++t) {
      const std::string& name = layout.tracks[t].name;
      if (i > 0) visit_force(visit, "articulated_force_" + name, i, art.track[t][i].articulated_force);
      for (int k = 0; k < nc; ++k) visit("acceleration_energy_" + name, i, k, art.track[t][i].acceleration_energy[k]);
    }
  }
  for (int k = 0; k < nc; ++k) visit(std::string("base_acceleration_energy"), kBodyless, k, art.base_acceleration_energy[k]);
}

// Solver sweep: outputs first (nu, coupling_torque, qdd, tau_ctrl, tau_cmd, tip_acceleration, set_acceleration, closure_error, saturated,
// dropped_pivots), then the intermediates (conf_energy, acceleration, correction_force).
template <class Scalar, class Visit>
void visit_fields(const Solution<Scalar>& s, Policy policy, Visit&& visit) {
  const int set_directions = static_cast<int>(s.nu.size()) - static_cast<int>(s.couplings);
  for (int k = 0; k < set_directions; ++k) visit(std::string("nu"), kBodyless, k, s.nu[k]);
  for (int k = set_directions; k < s.nu.size(); ++k) visit(std::string("coupling_torque"), kBodyless, k - set_directions, s.nu[k]);
  for (int i = 0; i < s.qdd.size(); ++i) visit(std::string("qdd"), kBodyless, i, s.qdd[i]);
  for (int i = 0; i < s.tau_ctrl.size(); ++i) visit(std::string("tau_ctrl"), kBodyless, i, s.tau_ctrl[i]);
  for (int i = 0; i < s.tau_cmd.size(); ++i) visit(std::string("tau_cmd"), kBodyless, i, s.tau_cmd[i]);
  visit_motion(visit, "tip_acceleration", kBodyless, s.tip_acceleration);
  for (std::size_t c = 0; c < s.set_acceleration.size(); ++c) {
    const auto& m = s.set_acceleration[c];
    const int at = 6 * static_cast<int>(c);
    for (int i = 0; i < 3; ++i) visit(std::string("set_acceleration"), kBodyless, at + i, m.angular[i]);
    for (int i = 0; i < 3; ++i) visit(std::string("set_acceleration"), kBodyless, at + 3 + i, m.linear[i]);
  }
  for (std::size_t c = 0; c < s.closure_error.size(); ++c) {
    visit_motion(visit, "closure_error", kBodyless, s.closure_error[c][0], 12 * static_cast<int>(c));
    visit_motion(visit, "closure_error", kBodyless, s.closure_error[c][1], 12 * static_cast<int>(c) + 6);
  }
  for (int i = 0; i < s.saturated.size(); ++i) visit(std::string("saturated"), kBodyless, i, s.saturated[i]);
  visit(std::string("dropped_pivots"), kBodyless, 0, s.dropped_pivots);
  visit(std::string("locked_joints"), kBodyless, 0, s.locked_joints);
  for (int k = 0; k < s.conf_energy.size(); ++k) visit(std::string("conf_energy"), kBodyless, k, s.conf_energy[k]);
  for (int i = 1; i < static_cast<int>(s.acceleration.size()); ++i) visit_motion(visit, "acceleration", i, s.acceleration[i]);
  if (policy == Policy::saturate_exact)
    for (int i = 1; i < static_cast<int>(s.correction_force.size()); ++i)
      visit_force(visit, "correction_force", i, s.correction_force[i]);
}

// The residuals' Jacobians (D8): per body 1..N base to tip, in the coordinates of (D8), then the
// matrices, row j (a joint's ρ, a direction's r) at [j * 2N]: the N q columns, then the N q̇ ones.
template <class Scalar, class Visit>
void visit_fields(const ResidualJacobians<Scalar>& J, Visit&& visit) {
  const int n = static_cast<int>(J.axis.size()) - 1;
  for (int i = 1; i <= n; ++i) {
    visit_matrix(visit, "frame_E", i, J.to_body[i].E);
    visit_matrix(visit, "frame_r", i, J.to_body[i].r);
    visit_motion(visit, "frame_axis", i, J.axis[i]);
    visit_motion(visit, "frame_velocity", i, J.velocity[i]);
    visit_motion(visit, "frame_axis_rate", i, J.axis_rate[i]);
    visit_motion(visit, "frame_acceleration", i, J.acceleration[i]);
  }
  for (int i = n; i >= 1; --i) {
    visit_matrix(visit, "composite_inertia", i, J.composite_inertia[i].A, 0);
    visit_matrix(visit, "composite_inertia", i, J.composite_inertia[i].B, 9);
    visit_matrix(visit, "composite_inertia", i, J.composite_inertia[i].C, 18);
    visit_matrix(visit, "composite_coriolis", i, J.composite_coriolis[i].T, 0);
    visit_matrix(visit, "composite_coriolis", i, J.composite_coriolis[i].s, 9);
    visit_force(visit, "composite_momentum", i, J.composite_momentum[i]);
    visit_force(visit, "composite_force", i, J.composite_force[i]);
  }
  for (int i = 1; i <= n; ++i) {
    visit_motion(visit, "acceleration_along_q", i, J.acceleration_along_q[i]);
    visit_motion(visit, "acceleration_along_qd", i, J.acceleration_along_qd[i]);
    visit_force(visit, "inertia_on_axis", i, J.inertia_on_axis[i]);
    visit_force(visit, "coriolis_on_axis", i, J.coriolis_on_axis[i]);
    visit_force(visit, "force_along_q", i, J.force_along_q[i]);
    visit_force(visit, "force_along_qd", i, J.force_along_qd[i]);
  }
  const auto rows = [&](const std::string& array, const auto& along_q, const auto& along_qd) {
    for (Eigen::Index r = 0; r < along_q.rows(); ++r)
      for (Eigen::Index x = 0; x < along_q.cols(); ++x) {
        visit(array, kBodyless, static_cast<int>(2 * r * n + x), along_q(r, x));
        visit(array, kBodyless, static_cast<int>((2 * r + 1) * n + x), along_qd(r, x));
      }
  };
  rows("d_rho", J.rho_q, J.rho_qd);
  rows("d_r", J.r_q, J.r_qd);
}

// The arrays of a Solution that a solve returns: those `outputs` lists, and what the status is made
// of (the rest are intermediates).
inline bool is_solution_output(const std::string& array, const SolveOutputs& outputs) {
  return outputs.lists(array) || array == "saturated" || array == "dropped_pivots" || array == "locked_joints";
}

}  // namespace sweepgen::solver
