// An independent dense rigid-body dynamics oracle, templated on the scalar: the tests use it in
// long double, `sweepgen report` in double as its "dense KKT" row.
//
// It shares nothing with generator/solver: no spatial transforms, no articulated bodies. Every
// quantity is computed in the base (root link) frame with classical vectors:
//   pose of body i:  R_i (body coordinates -> base coordinates), p_i (origin, base coordinates);
//   ω_i, v_i: angular velocity and velocity of body i's origin; ω̇_i, a_i their classical
//   derivatives, with a_0 = −g so that every a_i carries "minus gravity" (as the solver's Ẍ);
//   Newton–Euler about each body's origin (f = m a_o + ω̇×h + ω×(ω×h),
//   n_o = I_o ω̇ + ω×I_o ω + h×a_o, h = m c the first moment), forces carried inward.
// Only the chain's *data* (model::Chain: axes, tree transforms, inertias, frames) is read; the
// spatial types serve as plain containers of that data. A floating base's six coordinates (F5)
// are ordinary joints here, held at q = 0 (whatever q holds for them), with their own
// velocity-product terms: `in_solver_coordinates` turns their q̈ into the base's spatial
// acceleration, the solver's.
//
// Conventions shared with the solver (docs/derivation.md, section 1):
//   * a link frame's twist is [ω; v] in that frame's own coordinates, v the velocity of the
//     frame's origin; its "spatial acceleration minus gravity" is
//     [R^T ω̇; R^T (p̈ − g) − (R^T ω) × (R^T ṗ)];
//   * wrenches are [moment; force] in a link frame, about its origin;
//   * the body Jacobian J of a link frame maps q̇ to its twist; Ẍ = J q̈ + c with c the drift
//     (spatial acceleration minus gravity at q̈ = 0);
//   * joint torques include the rotor term d_i q̈_i; M(q) has d_i on its diagonal.
#pragma once

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "model/chain.hpp"

namespace sweepgen::oracle {

template <class Scalar>
class DenseDynamics {
 public:
  using V3 = Eigen::Matrix<Scalar, 3, 1>;
  using M3 = Eigen::Matrix<Scalar, 3, 3>;
  using Vec = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Mat = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Six = Eigen::Matrix<Scalar, 6, 1>;              // [angular; linear] or [moment; force]
  using Jacobian = Eigen::Matrix<Scalar, 6, Eigen::Dynamic>;

  struct Pose {
    M3 R = M3::Identity();  // frame coordinates -> base coordinates
    V3 p = V3::Zero();      // frame origin in base coordinates
  };

  // A wrench acting on the robot, in `link`'s frame about its origin, [moment; force].
  struct ExternalWrench {
    std::string link;
    Six wrench = Six::Zero();
  };

  // Everything about one body at one state, base coordinates.
  struct BodyMotion {
    Pose pose;
    V3 axis = V3::Zero();  // joint axis of this body's joint (unit), base coordinates
    V3 omega = V3::Zero(), velocity = V3::Zero();          // ω, origin velocity
    V3 omega_dot = V3::Zero(), acceleration = V3::Zero();  // ω̇, origin acceleration (minus g)
  };

  struct KktSolution {
    Vec qdd;      // joint accelerations
    Vec nu;       // Lagrange multipliers (constraint wrench on the tip = α ν)
    Mat E;        // α^T J M^-1 J^T α (Nc x Nc)
    Scalar cond;  // λmax/λmin of E (1 if Nc = 0, +inf if singular)
  };

  explicit DenseDynamics(const model::Chain& chain, const model::Vec3& gravity = model::Vec3(0, 0, -9.81));

  std::size_t dof() const { return n_; }

  // q̈ in the solver's coordinates: for a floating base, q̈_1..6 replaced by the root link's
  // spatial acceleration [ω̇; v̇] in its frame, gravity taken out (F5).
  Vec in_solver_coordinates(const Vec& q, const Vec& qd, const Vec& qdd) const;

  // Poses of bodies 0..N.
  std::vector<Pose> body_poses(const Vec& q) const;

  Pose link_pose(const Vec& q, const std::string& link) const;

  // Outward recursion of classical velocities and accelerations, bodies 0..N.
  std::vector<BodyMotion> body_motion(const Vec& q, const Vec& qd, const Vec& qdd, bool with_gravity = true) const;

  // Inverse dynamics: the joint torques (rotor terms d_i q̈_i included) that produce q̈ while
  // the wrenches `ext` act on the robot.
  Vec inverse_dynamics(const Vec& q, const Vec& qd, const Vec& qdd, const std::vector<ExternalWrench>& ext = {},
                       bool with_gravity = true) const;

  // M(q), column by column from inverse dynamics without gravity and velocity.
  Mat mass_matrix(const Vec& q) const;

  // b(q, q̇) = ID(q, q̇, 0): Coriolis, centrifugal and gravity torques.
  Vec bias(const Vec& q, const Vec& qd) const { return inverse_dynamics(q, qd, Vec::Zero(n_)); }

  // The potential energy of gravity, −g^T Σ_i (m_i p_i + R_i h_i) (h_i the first moment, body_poses'
  // p_i and R_i): with ½ q̇^T M q̇ the energy a fixed base without drivers and damping keeps.
  Scalar potential_energy(const Vec& q) const;

  // Body Jacobian of a link frame: its twist [ω; v] in its own coordinates is J q̇.
  Jacobian jacobian(const Vec& q, const std::string& link) const;

  // Twist [ω; v] of a link frame in its own coordinates.
  Six twist(const Vec& q, const Vec& qd, const std::string& link) const;

  // Spatial acceleration minus gravity of a link frame, in its own coordinates.
  Six spatial_acceleration(const Vec& q, const Vec& qd, const Vec& qdd, const std::string& link) const;

  // Drift c: the spatial acceleration minus gravity at q̈ = 0 (so Ẍ = J q̈ + c).
  Six drift(const Vec& q, const Vec& qd, const std::string& link) const;

  // Σ J_i^T F_ext,i: the joint torques equivalent to the external wrenches.
  Vec external_torque(const Vec& q, const std::vector<ExternalWrench>& ext) const;

  // Forward dynamics M^-1 (τ + Σ J^T F_ext − b).
  Vec forward_dynamics(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext) const;

  // Jc = rows α_k^T J_link(k): the constraint Jacobian of directions on any links (`links`: one
  // per column of α, 6 x Nc, each in its link's frame as [moment; force]).
  Mat constraint_jacobian(const Vec& q, const std::vector<std::string>& links, const Mat& alpha) const;
  // α_k^T c_link(k): the drift of each constraint direction.
  Vec constraint_drift(const Vec& q, const Vec& qd, const std::vector<std::string>& links, const Mat& alpha) const;

  // A frame fixed to a link: its pose in the link's frame (a URDF origin's convention).
  struct AttachedFrame {
    std::string link;
    M3 R = M3::Identity();
    V3 p = V3::Zero();
  };
  // Frame A relative to frame B, in A's coordinates (docs/derivation.md, L1, L2): v_rel = J q̇,
  // d/dt v_rel = J q̈ + drift, each from A's and B's own Jacobians, twists and drifts.
  struct RelativeMotion {
    Jacobian J;
    Six velocity, drift;
  };
  RelativeMotion relative_motion(const Vec& q, const Vec& qd, const AttachedFrame& A, const AttachedFrame& B) const;
  // How far A is from B (L3): [the rotation vector of R_B^T R_A, angle in [0, π]; R_A^T (p_A − p_B)].
  Six pose_error(const Vec& q, const AttachedFrame& A, const AttachedFrame& B) const;

  // Each <mimic> joint the chain moves coupled to its source, also moved, q_m = k q_s + o (M1): the
  // rows e_m^T − k e_s^T (rhs 0), whose force is the torque pair +1 on m, −k on s.
  static Mat coupling_rows(const model::Chain& chain);

  // Gauss' principle with any constraint rows Jc q̈ = rhs: M q̈ + b = τ + Jc^T ν. Full-pivot LU.
  KktSolution solve_rows(const Vec& q, const Vec& qd, const Vec& tau, const Mat& Jc, const Vec& rhs) const;

  // Gauss' principle with the constraints α_k^T Ẍ_link(k) = β_k:
  //   [ M   −Jc^T ] [q̈]   [ τ + Σ J_i^T F_ext,i − b ]
  //   [ Jc    0   ] [ν] = [ β − (α_k^T c_link(k))_k ],   Jc = (α_k^T J_link(k))_k,
  // i.e. M q̈ + b = τ + Σ J_i^T F_ext,i + Jc^T ν. Solved by full-pivot LU.
  KktSolution kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                  const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const;
  // The same system without E and its condition number: q̈ and ν only.
  KktSolution solve_kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                        const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const;
  // Every direction on one link (the chain's tip, say).
  KktSolution kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                  const std::string& link, const Mat& alpha, const Vec& beta) const;

  // The constraints the solver's documented pivot policy keeps (generator/solver/
  // constraint_multipliers.hpp; a policy rather than dynamics): LDL^T of E with diagonal
  // pivoting, each step taking the remaining direction with the largest ratio of its Schur-
  // complement diagonal to its own diagonal E_jj, a pivot <= tolerance * E_jj dropped.
  // Returns the indices of the kept constraints in pivot order.
  static std::vector<Eigen::Index> kept_constraints(const Mat& E, Scalar tolerance);

  // λmax/λmin of a symmetric PSD matrix (1 if empty, +inf if singular).
  static Scalar condition(const Mat& E);

  // E^A_cstr,0 = J M⁻¹ Jᵀ, what the inward sweep accumulates ((I3) down to the root), by LDLᵀ of
  // M; 0 × 0 for no rows (Eigen 3.4's triangular solve of an empty right-hand side is undefined
  // behaviour, reported by UBSan).
  static Mat constraint_energy(const Mat& M, const Mat& J);

 private:
  struct JointData {
    bool revolute = true;
    bool held_at_zero = false;  // a floating base's coordinate
    V3 axis = V3::UnitZ();
    M3 tree_rotation = M3::Identity();
    V3 tree_offset = V3::Zero();
    Scalar rotor = Scalar(0);
  };
  struct BodyData {
    Scalar mass = Scalar(0);
    V3 first_moment = V3::Zero();
    M3 inertia_origin = M3::Zero();
  };
  struct LinkData {
    std::size_t body = 0;
    M3 rotation = M3::Identity();  // link orientation in its body's coordinates
    V3 offset = V3::Zero();        // link origin in its body's coordinates
  };

  static Pose frame_pose(const Pose& body, const LinkData& l) { return {body.R * l.rotation, body.p + body.R * l.offset}; }
  // The world pose of a frame fixed to a link.
  Pose attached_pose(const Vec& q, const AttachedFrame& frame) const;

  // Joint i's position: q_i, or 0 for a floating base's coordinate.
  Scalar position(const Vec& q, std::size_t i) const { return joints_[i].held_at_zero ? Scalar(0) : q[i - 1]; }

  std::size_t n_;
  std::size_t root_body_ = 0;  // the root link's body of a floating base (6), else 0
  std::vector<std::size_t> parent_;  // model::Chain::parent
  V3 gravity_;
  std::vector<JointData> joints_;
  std::vector<BodyData> bodies_;
  std::map<std::string, LinkData> links_;
};

// Compiled once per scalar, for the report (double, oracle/dense_dynamics_double.cpp) and the tests
// (long double, oracle/dense_dynamics_long_double.cpp): the dense linear algebra behind M, the KKT solve and the eigenvalues took
// 15-40 s to compile in every file that included it.
extern template class DenseDynamics<double>;
extern template class DenseDynamics<long double>;

}  // namespace sweepgen::oracle
