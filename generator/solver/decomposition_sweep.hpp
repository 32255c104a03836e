// Inward sweep, tip to base: Alg. 1 and Alg. 2 of the paper as one recursion over tracks
// (docs/derivation.md, section 3).
//
// Per body i, p = λ(i) its parent, with U_i = M^A_i S_i, D_i = d_i + S_i^T U_i and
// P_i^T F = F − U_i D_i^-1 S_i^T F (I0), D_i^-1 := 0 where the joint-inertia policy locks joint i
// (J1) (without the test where it provably never does, J2, whose exact zeros of S_i^T P_i^T are
// written in), each child i adds to its parent (on a chain p = i-1 has one child):
//   M^A_p     += X_i^T P_i^T M^A_i X_i                       (from M^A_p = M_p)            (I1)
//   F^A_cstr,p += X_i^T (F^A_cstr,i − U_i D_i^-1 r_i)        (from own_cstr,p)             (I2)
//   E^A_cstr,p += E^A_cstr,i + r_i D_i^-1 r_i^T               (from 0)                      (I3)
// with the rows r_i = S_i^T F^A_cstr,i + τ_c,i, τ_c,i the couplings' unit torques at joint i (M2;
// 0 without couplings, when F − U D^-1 r is P_i^T F)
// and for every track t, with Fc = F^A_t,i (+ M^A_i Ẍb_i if t carries the bias) and
// u = Σ_{τ in t} τ_i − S_i^T Fc:
//   F^A_t,p += X_i^T (Fc + U_i D_i^-1 u)                     (from own_t,p)                (I4)
//   E^A_t,p += E^A_t,i + F^A_cstr,i^T ((Ẍb_i if bias) + S_i D_i^-1 u)  (from 0)            (I5)
// where own_t,i = (Fb_i if bias) − Σ_{external forces of t on body i} F_ext, and column k of
// own_cstr,i is X_link^T α_k when direction k's set acts on a link that body i carries, and for a set
// between two links −(^AX_b)^T α_k where its other link rides (L4), else 0 (a set's columns start at
// its bodies: outboard of them they are exactly zero); a loop's velocity-product term joins the bias
// track's E^A_t,0 (L5).
// The bias track reproduces F^A_b/E^A_b, a torque track F^A/E^A, an external-force track
// −F^A_ext/E^A_ext, and the single track of Alg. 1 the composed F^A_b/E^A_conf.
// Where (C5) applies, each constraint set's block of the (I3) matrix handed on by the last body that
// carries that set alone is kept (private_energy): the sum of the terms of its own joints.
// The rows r_i = S_i^T F^A_cstr,i are kept (constraint_row, for (S3)). With outward rows (I6,
// constraint_rows.hpp) the columns are not formed: r_i comes from outward propagation, and the
// bias and base-acceleration terms F^A_cstr^T Ẍ of (I5) and (S2) go, summed, into the bias
// track's E^A_t,0 (the policies all compose the bias track, so (S2) sees the same sum).
#pragma once

#include "solver/constraint_rows.hpp"
#include "solver/joint_inertia.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// Joint i's share of track t's driving torque, Σ_{τ in t} τ_i.
template <class Scalar>
Scalar track_torque(const Track& track, const DriverInputs<Scalar>& inputs, std::size_t i) {
  Scalar tau(0);
  for (std::size_t k : track.torques) tau += inputs.torques[k][i - 1];
  return tau;
}

// External force instance k where its link rides on body i, in body i's frame (0 elsewhere).
template <class Scalar>
spatial::Force<Scalar> external_own_force(const SolverModel<Scalar>& model, const DriverInputs<Scalar>& inputs,
                                          std::size_t k, std::size_t i) {
  return model.external_force_body[k] == i ? model.external_force_frame[k].apply_transpose(inputs.external_forces[k])
                                           : spatial::Force<Scalar>{};
}

// own_t,i: the forces that enter track t at body i.
template <class Scalar>
spatial::Force<Scalar> track_own_force(const SolverModel<Scalar>& model, const Track& track,
                                       const KinematicsState<Scalar>& kin, const DriverInputs<Scalar>& inputs,
                                       std::size_t i) {
  spatial::Force<Scalar> own = track.bias ? kin.body[i].bias_force : spatial::Force<Scalar>{};
  for (std::size_t k : track.external_forces) own -= external_own_force(model, inputs, k, i);
  return own;
}

// Column k of own_cstr,i: direction k's unit force where its set's frame A rides on body i, and for a
// set between two links its opposite where the other link rides, −(^AX_b)^T α_k (L4); none for a
// coupling, whose unit force is a joint torque (M2).
template <class Scalar>
spatial::Force<Scalar> constraint_own_force(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                            const DriverInputs<Scalar>& inputs, std::size_t k, std::size_t i) {
  spatial::Force<Scalar> own;
  if (k >= model.set_directions()) return own;
  const ConstraintSetModel<Scalar>& set = model.set_of(k);
  if (set.body == i) own = set.frame.apply_transpose(inputs.constraint_directions[k]);
  if (set.relative && set.other_body == i)
    own -= kin.loop[model.constraint_set_of[k]].X_other.apply_transpose(inputs.constraint_directions[k]);
  return own;
}

// Whether direction k's unit force enters at body i (L4).
template <class Scalar>
bool constraint_enters_at(const SolverModel<Scalar>& model, std::size_t k, std::size_t i) {
  if (k >= model.set_directions()) return false;
  const ConstraintSetModel<Scalar>& set = model.set_of(k);
  return set.body == i || (set.relative && set.other_body == i);
}

// α_k^T (v_A × ^AX_b Ẋ_b) of the sets between two links, 0 for the others: the velocity-product
// term of (L1), which the bias track's E^A_t,0 carries (L5).
template <class Scalar>
ConstraintVector<Scalar> loop_velocity_product_energy(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                                      const DriverInputs<Scalar>& inputs) {
  ConstraintVector<Scalar> energy = ConstraintVector<Scalar>::Zero(model.constraints());
  for (std::size_t s = 0; s < model.constraint_sets.size(); ++s) {
    const ConstraintSetModel<Scalar>& set = model.constraint_sets[s];
    for (std::size_t k = set.first; set.relative && k < set.first + set.count; ++k)
      energy[k] = spatial::dot(inputs.constraint_directions[k], kin.loop[s].velocity_product);
  }
  return energy;
}

// One step of a track's force recursion at body i: returns X_i^T (Fc + U_i D_i^-1 u), the
// contribution handed to its parent, and u through `u_out`.
template <class Scalar>
spatial::Force<Scalar> track_force_to_parent(const JointModel<Scalar>& joint, const BodyKinematics<Scalar>& body,
                                             const BodyArticulated<Scalar>& art, const spatial::Force<Scalar>& Fc,
                                             const Scalar& tau, Scalar& u_out) {
  u_out = tau - spatial::dot(Fc, joint.S);
  spatial::Force<Scalar> handed = Fc + art.U * (art.inverse_D * u_out);
  set_axis_component_to_torque(joint, handed, tau);  // (J2)
  return body.X.apply_transpose(handed);
}

// @pre kin from outward_sweep_base_to_tip for the same q, q̇; art sized by make_articulated_state.
template <class Scalar>
void decomposition_sweep_tip_to_base(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                     const DriverInputs<Scalar>& inputs, ArticulatedState<Scalar>& art) {
  const std::size_t n = model.dof();
  const std::size_t nc = model.constraints();
  const auto& tracks = model.layout.tracks;
  const bool outward_rows = model.constraint_rows == ConstraintRows::outward_rows;
  const std::vector<bool> reaches = bodies_reaching_a_set(model);

  // Start values: M^A_i = M_i, F^A_t,i = own_t,i, F^A_cstr,i = own_cstr,i, every E^A_i = 0; the
  // children of each body then add to it (a body's index is above its parent's, so all of its
  // children are done before it is read).
  for (std::size_t i = 0; i <= n; ++i) {
    if (i > 0) art.body[i].articulated_inertia = model.inertia[i];
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      if (i > 0) art.track[t][i].articulated_force = track_own_force(model, tracks[t], kin, inputs, i);
      art.track[t][i].acceleration_energy.setZero(nc);
    }
    for (std::size_t k = 0; k < nc; ++k) art.body[i].constraint_force[k] = constraint_own_force(model, kin, inputs, k, i);
    art.body[i].constraint_energy.setZero(nc, nc);
  }

  for (std::size_t i = n; i >= 1; --i) {
    const JointModel<Scalar>& joint = model.joints[i];
    const BodyKinematics<Scalar>& body = kin.body[i];
    const std::size_t p = model.parent[i];
    BodyArticulated<Scalar>& a = art.body[i];
    BodyArticulated<Scalar>& parent = art.body[p];

    a.U = a.articulated_inertia * joint.S;  // (I0)
    a.D = joint.rotor_inertia + spatial::dot(a.U, joint.S);
    // Joint-inertia policy (J1, solver/joint_inertia.hpp): D_i <= tol (d_i + tr block) is treated
    // as 0, branch-free: D_i^-1 := 0, so the joint is locked (no projection in (I1), q̈_i = 0)
    // and no Inf/NaN can arise where M(q) is singular.
    // Where the model's bounds prove it never locks (J2), D_i^-1 = 1 / D_i without the test.
    if (joint.can_lock) {
      const Scalar threshold = model.joint_inertia_tolerance * joint_inertia_scale(joint, a.articulated_inertia);
      a.locked = select_greater(a.D, threshold, Scalar(0), Scalar(1));
      a.inverse_D = select_greater(a.D, threshold, Scalar(1), Scalar(0)) / select_greater(a.D, threshold, a.D, Scalar(1));
    } else {
      a.locked = Scalar(0);
      a.inverse_D = Scalar(1) / a.D;
    }

    if (p > 0) {  // (I1)
      spatial::Inertia<Scalar> projected = a.articulated_inertia.minus_outer(a.U, a.inverse_D);
      zero_axis_row_and_column(joint, projected);  // (J2)
      parent.articulated_inertia = parent.articulated_inertia + projected.transformed_to_parent(body.X);
    }

    // (I2) or (I6), (I3)
    ConstraintVector<Scalar> s(nc);
    if (outward_rows) {
      s = constraint_row_outward(model, kin, art, inputs, reaches, i);
    } else {
      for (std::size_t k = 0; k < nc; ++k) s[k] = spatial::dot(a.constraint_force[k], joint.S);
      for (std::size_t k = 0; k < nc; ++k)
        if (coupling_acts_at(model, k, i)) s[k] += coupling_torque_at(model, k, i);  // (M2)
      for (std::size_t k = 0; k < nc; ++k) {
        spatial::Force<Scalar> projected = a.constraint_force[k] - a.U * (a.inverse_D * s[k]);
        // (J2): S_i^T of it is −τ_c,i, exactly (M2)
        const Scalar axis_torque = coupling_acts_at(model, k, i) ? Scalar(-coupling_torque_at(model, k, i)) : Scalar(0);
        set_axis_component_to_torque(joint, projected, axis_torque);
        parent.constraint_force[k] = parent.constraint_force[k] + body.X.apply_transpose(projected);
      }
    }
    a.constraint_row = s;
    const ConstraintMatrix<Scalar> handed = a.constraint_energy + s * (a.inverse_D * s.transpose());
    parent.constraint_energy = parent.constraint_energy + handed;
    for (std::size_t c = 0; c < model.private_top.size(); ++c) {  // (C5): set c's block, complete here
      const ConstraintSetModel<Scalar>& set = model.constraint_sets[c];
      const auto first = static_cast<Eigen::Index>(set.first), count = static_cast<Eigen::Index>(set.count);
      if (model.private_top[c] == i) art.private_energy.block(first, first, count, count) = handed.block(first, first, count, count);
    }

    // (I4), (I5)
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      const TrackBody<Scalar>& here = art.track[t][i];
      TrackBody<Scalar>& up = art.track[t][p];
      spatial::Force<Scalar> Fc = here.articulated_force;
      if (tracks[t].bias) Fc += a.articulated_inertia * body.bias_acceleration;
      Scalar u;
      const spatial::Force<Scalar> handed_up =
          track_force_to_parent(joint, body, a, Fc, track_torque(tracks[t], inputs, i), u);
      if (p > 0) up.articulated_force += handed_up;
      ConstraintVector<Scalar> energy = here.acceleration_energy;
      for (std::size_t k = 0; k < nc; ++k) {
        energy[k] += s[k] * (a.inverse_D * u);
        if (tracks[t].bias && !outward_rows) energy[k] += spatial::dot(a.constraint_force[k], body.bias_acceleration);
      }
      up.acceleration_energy = up.acceleration_energy + energy;
    }
  }

  // The velocity-product term of the sets between two links joins the bias track (L5).
  if (model.has_relative_sets())
    for (std::size_t t = 0; t < tracks.size(); ++t)
      if (tracks[t].bias) art.track[t][0].acceleration_energy += loop_velocity_product_energy(model, kin, inputs);
  // F^A_cstr,0^T Ẍ_0 for (S2); with outward rows, summed with the bias terms into the bias track.
  if (!outward_rows) {
    for (std::size_t k = 0; k < nc; ++k)
      art.base_acceleration_energy[k] = spatial::dot(art.body[0].constraint_force[k], kin.base_acceleration);
    return;
  }
  art.base_acceleration_energy.setZero(nc);
  for (std::size_t t = 0; t < tracks.size(); ++t)
    if (tracks[t].bias) art.track[t][0].acceleration_energy += bias_energy_outward(model, kin, art, inputs);
}

}  // namespace sweepgen::solver
