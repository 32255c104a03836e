// Inward sweep, tip to base: Alg. 1 and Alg. 2 of the paper as one recursion over tracks
// (docs/derivation.md, section 3).
//
// Per body i, with U_i = M^A_i S_i, D_i = d_i + S_i^T U_i and P_i^T F = F − U_i D_i^-1 S_i^T F (I0),
// D_i^-1 := 0 where the joint-inertia policy locks joint i (J1):
//   M^A_{i-1}     = M_{i-1} + X_i^T P_i^T M^A_i X_i                                  (I1)
//   F^A_cstr,i-1  = own_cstr,i-1 + X_i^T P_i^T F^A_cstr,i                             (I2)
//   E^A_cstr,i-1  = E^A_cstr,i + F^A_cstr,i^T S_i D_i^-1 S_i^T F^A_cstr,i            (I3)
// and for every track t, with Fc = F^A_t,i (+ M^A_i Ẍb_i if t carries the bias) and
// u = Σ_{τ in t} τ_i − S_i^T Fc:
//   F^A_t,i-1 = own_t,i-1 + X_i^T (Fc + U_i D_i^-1 u)                                (I4)
//   E^A_t,i-1 = E^A_t,i + F^A_cstr,i^T ((Ẍb_i if bias) + S_i D_i^-1 u)              (I5)
// where own_t,i = (Fb_i if bias) − Σ_{external forces of t on body i} F_ext, and column k of
// own_cstr,i is X_link^T α_k when direction k's set acts on a link that body i carries, else 0
// (a set's columns start at its body: outboard of it they are exactly zero).
// The bias track reproduces F^A_b/E^A_b, a torque track F^A/E^A, an external-force track
// −F^A_ext/E^A_ext, and the single track of Alg. 1 the composed F^A_b/E^A_conf.
#pragma once

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

// own_t,i: the forces that enter track t at body i.
template <class Scalar>
spatial::Force<Scalar> track_own_force(const SolverModel<Scalar>& model, const Track& track,
                                       const KinematicsState<Scalar>& kin, const DriverInputs<Scalar>& inputs,
                                       std::size_t i) {
  spatial::Force<Scalar> own = track.bias ? kin.body[i].bias_force : spatial::Force<Scalar>{};
  for (std::size_t k : track.external_forces)
    if (model.external_force_body[k] == i)
      own -= model.external_force_frame[k].apply_transpose(inputs.external_forces[k]);
  return own;
}

// Column k of own_cstr,i: direction k's unit force where its set's link rides on body i.
template <class Scalar>
spatial::Force<Scalar> constraint_own_force(const SolverModel<Scalar>& model, const DriverInputs<Scalar>& inputs,
                                            std::size_t k, std::size_t i) {
  const ConstraintSetModel<Scalar>& set = model.set_of(k);
  return set.body == i ? set.frame.apply_transpose(inputs.constraint_directions[k]) : spatial::Force<Scalar>{};
}

// One step of a track's force recursion at body i: returns X_i^T (Fc + U_i D_i^-1 u), the
// contribution handed to body i-1, and u through `u_out`.
template <class Scalar>
spatial::Force<Scalar> track_force_to_parent(const JointModel<Scalar>& joint, const BodyKinematics<Scalar>& body,
                                             const BodyArticulated<Scalar>& art, const spatial::Force<Scalar>& Fc,
                                             const Scalar& tau, Scalar& u_out) {
  u_out = tau - spatial::dot(Fc, joint.S);
  return body.X.apply_transpose(Fc + art.U * (art.inverse_D * u_out));
}

// @pre kin from outward_sweep_base_to_tip for the same q, q̇; art sized by make_articulated_state.
template <class Scalar>
void decomposition_sweep_tip_to_base(const SolverModel<Scalar>& model, const KinematicsState<Scalar>& kin,
                                     const DriverInputs<Scalar>& inputs, ArticulatedState<Scalar>& art) {
  const std::size_t n = model.dof();
  const std::size_t nc = model.constraints();
  const auto& tracks = model.layout.tracks;

  // Start values: M^A_i = M_i, F^A_t,i = own_t,i, F^A_cstr,N = own_cstr,N, all E^A_N = 0.
  for (std::size_t i = 1; i <= n; ++i) {
    art.body[i].articulated_inertia = model.inertia[i];
    for (std::size_t t = 0; t < tracks.size(); ++t)
      art.track[t][i].articulated_force = track_own_force(model, tracks[t], kin, inputs, i);
  }
  for (std::size_t k = 0; k < nc; ++k)
    art.body[n].constraint_force[k] = constraint_own_force(model, inputs, k, n);
  art.body[n].constraint_energy.setZero(nc, nc);
  for (std::size_t t = 0; t < tracks.size(); ++t) art.track[t][n].acceleration_energy.setZero(nc);

  for (std::size_t i = n; i >= 1; --i) {
    const JointModel<Scalar>& joint = model.joints[i];
    const BodyKinematics<Scalar>& body = kin.body[i];
    BodyArticulated<Scalar>& a = art.body[i];
    BodyArticulated<Scalar>& parent = art.body[i - 1];

    a.U = a.articulated_inertia * joint.S;  // (I0)
    a.D = joint.rotor_inertia + spatial::dot(a.U, joint.S);
    // Joint-inertia policy (J1, solver/joint_inertia.hpp): D_i <= tol (d_i + tr block) is treated
    // as 0, branch-free: D_i^-1 := 0, so the joint is locked (no projection in (I1), q̈_i = 0)
    // and no Inf/NaN can arise where M(q) is singular.
    const Scalar threshold = model.joint_inertia_tolerance * joint_inertia_scale(joint, a.articulated_inertia);
    a.locked = select_greater(a.D, threshold, Scalar(0), Scalar(1));
    a.inverse_D = select_greater(a.D, threshold, Scalar(1), Scalar(0)) / select_greater(a.D, threshold, a.D, Scalar(1));

    if (i > 1)  // (I1)
      parent.articulated_inertia = parent.articulated_inertia +
                                   a.articulated_inertia.minus_outer(a.U, a.inverse_D).transformed_to_parent(body.X);

    // (I2), (I3)
    ConstraintVector<Scalar> s(nc);
    for (std::size_t k = 0; k < nc; ++k) s[k] = spatial::dot(a.constraint_force[k], joint.S);
    for (std::size_t k = 0; k < nc; ++k)
      parent.constraint_force[k] = constraint_own_force(model, inputs, k, i - 1) +
                                   body.X.apply_transpose(a.constraint_force[k] - a.U * (a.inverse_D * s[k]));
    parent.constraint_energy = a.constraint_energy + s * (a.inverse_D * s.transpose());

    // (I4), (I5)
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      const TrackBody<Scalar>& here = art.track[t][i];
      TrackBody<Scalar>& up = art.track[t][i - 1];
      spatial::Force<Scalar> Fc = here.articulated_force;
      if (tracks[t].bias) Fc += a.articulated_inertia * body.bias_acceleration;
      Scalar u;
      const spatial::Force<Scalar> handed_up =
          track_force_to_parent(joint, body, a, Fc, track_torque(tracks[t], inputs, i), u);
      if (i > 1) up.articulated_force += handed_up;
      up.acceleration_energy = here.acceleration_energy;
      for (std::size_t k = 0; k < nc; ++k) {
        up.acceleration_energy[k] += s[k] * (a.inverse_D * u);
        if (tracks[t].bias) up.acceleration_energy[k] += spatial::dot(a.constraint_force[k], body.bias_acceleration);
      }
    }
  }
}

}  // namespace sweepgen::solver
