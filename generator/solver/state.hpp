// Everything the sweeps compute, split by what it depends on (docs/derivation.md, "State"):
//   KinematicsState   q, q̇                        outward sweep
//   ArticulatedState  q, q̇, drivers, F_cstr        inward (decomposition) sweep
//   Solution          + setpoints E_cstr, policy    solver sweep
// Arrays are indexed by body 0..N (0 = base); joint vectors (q, τ) are 0-based, q[i-1] is
// joint i. Every field stays readable after a solve.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "solver/drivers.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::solver {

template <class Scalar> using JointVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
template <class Scalar> using ConstraintVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1, 0, kMaxConstraints, 1>;
template <class Scalar>
using ConstraintMatrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxConstraints, kMaxConstraints>;
// Nc unit constraint forces, one column each (F_cstr, 6 x Nc).
template <class Scalar> using ConstraintForces = std::array<spatial::Force<Scalar>, kMaxConstraints>;

template <class Scalar>
struct DriverInputs {
  std::vector<JointVector<Scalar>> torques;                 // τff per torque instance
  std::vector<spatial::Force<Scalar>> external_forces;      // per instance, link frame, about its origin
  ConstraintForces<Scalar> constraint_directions;           // α_k in the frame of direction k's set's link

  static DriverInputs sized(const DriverLayout& layout, std::size_t n) {
    DriverInputs d;
    d.torques.assign(layout.torques.size(), JointVector<Scalar>::Zero(n));
    d.external_forces.resize(layout.external_forces.size());
    return d;
  }
};

template <class Scalar>
struct BodyKinematics {
  spatial::Transform<Scalar> X;           // X_i = iX_λ(i)(q_i)
  spatial::Motion<Scalar> velocity;       // Ẋ_i
  spatial::Motion<Scalar> bias_acceleration;  // Ẍb_i = Ẋ_i × S_i q̇_i
  spatial::Force<Scalar> bias_force;      // Fb_i = Ẋ_i ×* (M_i Ẋ_i)
};

// A set between two links (docs/derivation.md, (L1)), A on body a, B on body b: what the outward
// sweep gives its rows.
template <class Scalar>
struct LoopKinematics {
  bool between_links = false;                   // false: a set on one link, the rest unused
  spatial::Transform<Scalar> X_other;          // ^AX_b: body b's coordinates -> A's
  spatial::Motion<Scalar> relative_velocity;   // v_rel = v_A − ^AX_b Ẋ_b
  spatial::Motion<Scalar> velocity_product;    // v_A × ^AX_b Ẋ_b
};

template <class Scalar>
struct KinematicsState {
  std::vector<BodyKinematics<Scalar>> body;  // 0..N
  spatial::Motion<Scalar> base_acceleration;  // Ẍ_0 = −[0; g], or −[0; Rᵀ g] for a floating base (O4)
  std::vector<LoopKinematics<Scalar>> loop;   // per constraint set; read for the sets between two links

  static KinematicsState sized(std::size_t n, std::size_t constraint_sets = 0) {
    KinematicsState kin;
    kin.body.resize(n + 1);
    kin.loop.resize(constraint_sets);
    return kin;
  }
};

template <class Scalar>
struct BodyArticulated {
  spatial::Inertia<Scalar> articulated_inertia;  // M^A_i
  spatial::Force<Scalar> U;                      // M^A_i S_i
  Scalar D{};                                    // d_i + S_i^T M^A_i S_i
  Scalar inverse_D{};                            // 0 where the joint is locked
  Scalar locked{};                               // 1 where D_i fell below the joint-inertia tolerance, else 0
  ConstraintForces<Scalar> constraint_force;    // F^A_cstr,i (Nc columns; not formed with outward rows, I6)
  ConstraintVector<Scalar> constraint_row;      // r_i = S_i^T F^A_cstr,i (Nc), body 1..N
  ConstraintMatrix<Scalar> constraint_energy;   // E^A_cstr,i (Nc x Nc)
};

template <class Scalar>
struct TrackBody {
  spatial::Force<Scalar> articulated_force;     // F^A_track,i (bias sign: subtracted in q̈)
  ConstraintVector<Scalar> acceleration_energy; // E^A_track,i
};

template <class Scalar>
struct ArticulatedState {
  std::vector<BodyArticulated<Scalar>> body;     // 0..N; body[0] holds F^A_cstr,0, E^A_cstr,0
  std::vector<std::vector<TrackBody<Scalar>>> track;  // [track][body]
  // F^A_cstr,0^T Ẍ_0, what the base's acceleration (gravity) adds to the constraint's
  // acceleration energy (S2); with outward rows (I6) it is in the bias track's E^A_t,0 and 0 here.
  ConstraintVector<Scalar> base_acceleration_energy;
  // (C5): the block-diagonal lower bound B of E^A_cstr,0, each set's block where it is formed
  // (SolverModel::private_top), 0 elsewhere.
  ConstraintMatrix<Scalar> private_energy;

  static ArticulatedState sized(std::size_t n, std::size_t nc, std::size_t tracks) {
    ArticulatedState s;
    s.body.resize(n + 1);
    for (auto& body : s.body) body.constraint_energy.setZero(nc, nc);
    s.private_energy.setZero(nc, nc);
    TrackBody<Scalar> zero;
    zero.acceleration_energy.setZero(nc);
    s.track.assign(tracks, std::vector<TrackBody<Scalar>>(n + 1, zero));
    s.base_acceleration_energy.setZero(nc);
    return s;
  }
};

enum Status : unsigned {
  status_ok = 0,
  status_constraint_rank_deficient = 1u << 0,  // a pivot of E^A_cstr,0 fell below tolerance
  status_saturated = 1u << 1,                  // a saturating policy clamped a torque
  status_joint_inertia_singular = 1u << 3,     // a joint's D_i fell below tolerance: joint locked (q̈_i = 0)
  status_not_finite = 1u << 2,                 // NaN/Inf in an input (q, q̇, a driver, E_cstr) or a result
};

template <class Scalar>
struct Solution {
  // ν, Lagrange multipliers (constraint wrench = F_cstr ν): the sets' Nc, then the last `couplings`
  // those of the coupled <mimic> joints, their transmissions' torques (M2; output coupling_torque).
  ConstraintVector<Scalar> nu;
  std::size_t couplings = 0;
  ConstraintVector<Scalar> conf_energy;      // E_conf
  Scalar dropped_pivots{};                   // count of E^A_cstr,0 pivots treated as zero
  Scalar pivoted_path{};                     // 1 where ν came from the pivoted factorisation (C2, C3), 0
                                             // from the natural order (C4); not an output of generated code
  Scalar locked_joints{};                    // count of joints locked by the joint-inertia policy
  JointVector<Scalar> tau_ctrl;              // τctrl (articulated share)
  JointVector<Scalar> qdd;                   // q̈
  JointVector<Scalar> tau_cmd;               // τcmd, the torque that realises q̈
  JointVector<Scalar> saturated;             // 1 where the policy clamped joint i's torque, else 0
  std::vector<spatial::Motion<Scalar>> acceleration;  // Ẍ_i (spatial, minus gravity), 0..N
  std::vector<spatial::Force<Scalar>> correction_force;  // saturate_exact: F^A of τ_applied − τff, 0..N
  std::vector<spatial::Force<Scalar>> transmitted_force;  // f_i of (T1) or (T2): what joint i transmits, 0..N
  spatial::Motion<Scalar> tip_acceleration;  // Ẍ of the tip frame, in the tip frame
  // Ẍ of each listed constraint set's link, in its frame (DriverLayout::listed_sets; none for the
  // tip set of the short forms, whose Ẍ is tip_acceleration).
  std::vector<spatial::Motion<Scalar>> set_acceleration;
  // Per set between two links (DriverLayout::loop_sets), in set order: its pose error (L3) and v_rel
  // (L1) (solver/closure_error.hpp).
  std::vector<std::array<spatial::Motion<Scalar>, 2>> closure_error;

  // `nc`: every direction, the couplings' among them.
  static Solution sized(std::size_t n, std::size_t nc, std::size_t listed_sets, std::size_t loop_sets = 0,
                        std::size_t couplings = 0) {
    Solution s;
    s.couplings = couplings;
    for (auto* v : {&s.tau_ctrl, &s.qdd, &s.tau_cmd, &s.saturated}) v->setZero(n);
    s.nu.setZero(nc);
    s.conf_energy.setZero(nc);
    s.acceleration.resize(n + 1);
    s.correction_force.resize(n + 1);
    s.transmitted_force.resize(n + 1);
    s.set_acceleration.resize(listed_sets);
    s.closure_error.reserve(loop_sets);
    return s;
  }
};

}  // namespace sweepgen::solver
