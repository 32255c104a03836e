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

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
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

  explicit DenseDynamics(const model::Chain& chain, const model::Vec3& gravity = model::Vec3(0, 0, -9.81))
      : n_(chain.dof()), root_body_(chain.base_coordinates()), parent_(chain.parent), gravity_(gravity.cast<Scalar>()) {
    joints_.resize(n_ + 1);
    bodies_.resize(n_ + 1);
    for (std::size_t i = 1; i <= n_; ++i) {
      const model::Joint& j = chain.joints[i];
      JointData& jd = joints_[i];
      jd.revolute = j.type == model::JointType::revolute;
      jd.held_at_zero = j.floating_base_coordinate;
      jd.axis = j.axis.cast<Scalar>();
      // Tree transform {E, r}: E rotates parent coordinates into joint-frame coordinates,
      // so the joint frame's orientation in the parent is E^T; r is its origin in the parent.
      jd.tree_rotation = j.tree_transform.E.transpose().cast<Scalar>();
      jd.tree_offset = j.tree_transform.r.cast<Scalar>();
      jd.rotor = Scalar(j.rotor_inertia);
      // Inertia blocks [A B; B^T C] = [I_o, h×; -h×, m 1]: read m, h and I_o back.
      const model::Inertia& I = chain.bodies[i].inertia;
      BodyData& bd = bodies_[i];
      bd.mass = Scalar(I.C(0, 0));
      bd.first_moment = V3(Scalar(I.B(2, 1)), Scalar(I.B(0, 2)), Scalar(I.B(1, 0)));
      bd.inertia_origin = I.A.cast<Scalar>();
    }
    for (const auto& [name, frame] : chain.frames) {
      LinkData ld;
      ld.body = frame.body;
      ld.rotation = frame.X.E.transpose().template cast<Scalar>();
      ld.offset = frame.X.r.template cast<Scalar>();
      links_[name] = ld;
    }
  }

  std::size_t dof() const { return n_; }

  // q̈ in the solver's coordinates: for a floating base, q̈_1..6 replaced by the root link's
  // spatial acceleration [ω̇; v̇] in its frame, gravity taken out (F5).
  Vec in_solver_coordinates(const Vec& q, const Vec& qd, const Vec& qdd) const {
    Vec out = qdd;
    if (root_body_ == 0) return out;
    const BodyMotion root = body_motion(q, qd, qdd)[root_body_];
    const M3 Rt = root.pose.R.transpose();
    const V3 omega = Rt * root.omega;
    out.head(3) = Rt * root.omega_dot;
    out.segment(3, 3) = Rt * (root.acceleration + gravity_) - omega.cross(Rt * root.velocity);
    return out;
  }

  // Poses of bodies 0..N.
  std::vector<Pose> body_poses(const Vec& q) const {
    std::vector<Pose> pose(n_ + 1);
    for (std::size_t i = 1; i <= n_; ++i) {
      const JointData& j = joints_[i];
      const Pose& up = pose[parent_[i]];
      const M3 R_joint = up.R * j.tree_rotation;  // joint frame at q = 0
      pose[i].p = up.p + up.R * j.tree_offset;
      if (j.revolute) {
        pose[i].R = R_joint * M3(Eigen::AngleAxis<Scalar>(position(q, i), j.axis));
      } else {
        pose[i].R = R_joint;
        pose[i].p += R_joint * (j.axis * position(q, i));
      }
    }
    return pose;
  }

  Pose link_pose(const Vec& q, const std::string& link) const {
    const LinkData& l = links_.at(link);
    const Pose body = body_poses(q)[l.body];
    return {body.R * l.rotation, body.p + body.R * l.offset};
  }

  // Outward recursion of classical velocities and accelerations, bodies 0..N.
  std::vector<BodyMotion> body_motion(const Vec& q, const Vec& qd, const Vec& qdd, bool with_gravity = true) const {
    const std::vector<Pose> pose = body_poses(q);
    std::vector<BodyMotion> m(n_ + 1);
    if (with_gravity) m[0].acceleration = -gravity_;
    for (std::size_t i = 1; i <= n_; ++i) {
      const JointData& j = joints_[i];
      const BodyMotion& up = m[parent_[i]];
      BodyMotion& b = m[i];
      b.pose = pose[i];
      b.axis = pose[i].R * j.axis;  // the joint's rotation leaves its own axis invariant
      const V3 d = pose[i].p - pose[parent_[i]].p;
      b.omega = up.omega;
      b.omega_dot = up.omega_dot;
      b.velocity = up.velocity + up.omega.cross(d);
      b.acceleration = up.acceleration + up.omega_dot.cross(d) + up.omega.cross(up.omega.cross(d));
      if (j.revolute) {
        b.omega += b.axis * qd[i - 1];
        b.omega_dot += b.axis * qdd[i - 1] + up.omega.cross(b.axis * qd[i - 1]);
      } else {
        b.velocity += b.axis * qd[i - 1];
        b.acceleration += b.axis * qdd[i - 1] + Scalar(2) * up.omega.cross(b.axis * qd[i - 1]);
      }
    }
    return m;
  }

  // Inverse dynamics: the joint torques (rotor terms d_i q̈_i included) that produce q̈ while
  // the wrenches `ext` act on the robot.
  Vec inverse_dynamics(const Vec& q, const Vec& qd, const Vec& qdd, const std::vector<ExternalWrench>& ext = {},
                       bool with_gravity = true) const {
    const std::vector<BodyMotion> m = body_motion(q, qd, qdd, with_gravity);
    // Net force and moment (about the body origin) each body needs, minus the external ones.
    std::vector<V3> force(n_ + 1, V3::Zero()), moment(n_ + 1, V3::Zero());
    for (std::size_t i = 1; i <= n_; ++i) {
      const BodyData& bd = bodies_[i];
      const BodyMotion& b = m[i];
      const V3 h = b.pose.R * bd.first_moment;
      const M3 I = b.pose.R * bd.inertia_origin * b.pose.R.transpose();
      force[i] = bd.mass * b.acceleration + b.omega_dot.cross(h) + b.omega.cross(b.omega.cross(h));
      moment[i] = I * b.omega_dot + b.omega.cross(I * b.omega) + h.cross(b.acceleration);
    }
    for (const ExternalWrench& e : ext) {
      const LinkData& l = links_.at(e.link);
      if (l.body == 0) continue;  // acts on the fixed base
      const Pose& body = m[l.body].pose;
      const M3 R_link = body.R * l.rotation;
      const V3 f = R_link * e.wrench.template tail<3>();
      const V3 n_link = R_link * e.wrench.template head<3>();
      force[l.body] -= f;
      moment[l.body] -= n_link + (body.R * l.offset).cross(f);
    }
    // Bodies beyond i (higher indices) are done first: each adds what it transmits to its parent,
    // the moment moved to the parent's origin.
    Vec tau(n_);
    for (std::size_t i = n_; i >= 1; --i) {
      const V3& f = force[i];
      const V3& n = moment[i];
      tau[i - 1] = (joints_[i].revolute ? m[i].axis.dot(n) : m[i].axis.dot(f)) + joints_[i].rotor * qdd[i - 1];
      const std::size_t up = parent_[i];
      force[up] += f;
      moment[up] += n + (m[i].pose.p - m[up].pose.p).cross(f);
    }
    return tau;
  }

  // M(q), column by column from inverse dynamics without gravity and velocity.
  Mat mass_matrix(const Vec& q) const {
    Mat M(n_, n_);
    const Vec zero = Vec::Zero(n_);
    for (std::size_t k = 0; k < n_; ++k) M.col(k) = inverse_dynamics(q, zero, Vec::Unit(n_, k), {}, false);
    return M;
  }

  // b(q, q̇) = ID(q, q̇, 0): Coriolis, centrifugal and gravity torques.
  Vec bias(const Vec& q, const Vec& qd) const { return inverse_dynamics(q, qd, Vec::Zero(n_)); }

  // Body Jacobian of a link frame: its twist [ω; v] in its own coordinates is J q̇.
  Jacobian jacobian(const Vec& q, const std::string& link) const {
    const LinkData& l = links_.at(link);
    const Vec zero = Vec::Zero(n_);
    const std::vector<BodyMotion> m = body_motion(q, zero, zero, false);
    const Pose L = frame_pose(m[l.body].pose, l);
    Jacobian J = Jacobian::Zero(6, n_);
    for (std::size_t j = l.body; j > 0; j = parent_[j]) {  // the joints that move the link
      const V3& z = m[j].axis;
      if (joints_[j].revolute) {
        J.col(j - 1) << L.R.transpose() * z, L.R.transpose() * z.cross(L.p - m[j].pose.p);
      } else {
        J.col(j - 1) << V3::Zero(), L.R.transpose() * z;
      }
    }
    return J;
  }

  // Twist [ω; v] of a link frame in its own coordinates.
  Six twist(const Vec& q, const Vec& qd, const std::string& link) const {
    const LinkData& l = links_.at(link);
    const BodyMotion b = body_motion(q, qd, Vec::Zero(n_), false)[l.body];
    const Pose L = frame_pose(b.pose, l);
    Six t;
    t << L.R.transpose() * b.omega, L.R.transpose() * (b.velocity + b.omega.cross(b.pose.R * l.offset));
    return t;
  }

  // Spatial acceleration minus gravity of a link frame, in its own coordinates.
  Six spatial_acceleration(const Vec& q, const Vec& qd, const Vec& qdd, const std::string& link) const {
    const LinkData& l = links_.at(link);
    const BodyMotion b = body_motion(q, qd, qdd, true)[l.body];
    const Pose L = frame_pose(b.pose, l);
    const V3 r = b.pose.R * l.offset;
    const V3 v = b.velocity + b.omega.cross(r);
    const V3 a = b.acceleration + b.omega_dot.cross(r) + b.omega.cross(b.omega.cross(r));
    const V3 w_local = L.R.transpose() * b.omega;
    Six acc;
    acc << L.R.transpose() * b.omega_dot, L.R.transpose() * a - w_local.cross(L.R.transpose() * v);
    return acc;
  }

  // Drift c: the spatial acceleration minus gravity at q̈ = 0 (so Ẍ = J q̈ + c).
  Six drift(const Vec& q, const Vec& qd, const std::string& link) const {
    return spatial_acceleration(q, qd, Vec::Zero(n_), link);
  }

  // Σ J_i^T F_ext,i: the joint torques equivalent to the external wrenches.
  Vec external_torque(const Vec& q, const std::vector<ExternalWrench>& ext) const {
    Vec tau = Vec::Zero(n_);
    for (const ExternalWrench& e : ext) tau += jacobian(q, e.link).transpose() * e.wrench;
    return tau;
  }

  // Forward dynamics M^-1 (τ + Σ J^T F_ext − b).
  Vec forward_dynamics(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext) const {
    return mass_matrix(q).fullPivLu().solve(tau + external_torque(q, ext) - bias(q, qd));
  }

  // Jc = rows α_k^T J_link(k): the constraint Jacobian of directions on any links (`links`: one
  // per column of α, 6 x Nc, each in its link's frame as [moment; force]).
  Mat constraint_jacobian(const Vec& q, const std::vector<std::string>& links, const Mat& alpha) const {
    Mat Jc(alpha.cols(), static_cast<Eigen::Index>(n_));
    for (Eigen::Index k = 0; k < alpha.cols(); ++k)
      Jc.row(k) = alpha.col(k).transpose() * jacobian(q, links.at(static_cast<std::size_t>(k)));
    return Jc;
  }
  // α_k^T c_link(k): the drift of each constraint direction.
  Vec constraint_drift(const Vec& q, const Vec& qd, const std::vector<std::string>& links, const Mat& alpha) const {
    Vec c(alpha.cols());
    for (Eigen::Index k = 0; k < alpha.cols(); ++k)
      c[k] = alpha.col(k).dot(drift(q, qd, links.at(static_cast<std::size_t>(k))));
    return c;
  }

  // Gauss' principle with the constraints α_k^T Ẍ_link(k) = β_k:
  //   [ M   −Jc^T ] [q̈]   [ τ + Σ J_i^T F_ext,i − b ]
  //   [ Jc    0   ] [ν] = [ β − (α_k^T c_link(k))_k ],   Jc = (α_k^T J_link(k))_k,
  // i.e. M q̈ + b = τ + Σ J_i^T F_ext,i + Jc^T ν. Solved by full-pivot LU.
  KktSolution kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                  const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const {
    KktSolution s = solve_kkt(q, qd, tau, ext, links, alpha, beta);
    const Mat Jc = constraint_jacobian(q, links, alpha);
    // (Eigen 3.4's triangular solve binds a reference to the null data of an empty right-hand
    // side, undefined behaviour that UBSan reports: no solve for Nc = 0.)
    s.E = alpha.cols() > 0 ? Mat(Jc * mass_matrix(q).ldlt().solve(Jc.transpose())) : Mat(0, 0);
    s.cond = condition(s.E);
    return s;
  }
  // The same system without E and its condition number: q̈ and ν only.
  KktSolution solve_kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                        const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const {
    const Eigen::Index nc = alpha.cols();
    const Mat M = mass_matrix(q);
    const Mat Jc = constraint_jacobian(q, links, alpha);
    Mat K = Mat::Zero(n_ + nc, n_ + nc);
    K.topLeftCorner(n_, n_) = M;
    K.topRightCorner(n_, nc) = -Jc.transpose();
    K.bottomLeftCorner(nc, n_) = Jc;
    Vec rhs(n_ + nc);
    rhs.head(n_) = tau + external_torque(q, ext) - bias(q, qd);
    rhs.tail(nc) = beta - constraint_drift(q, qd, links, alpha);
    const Vec x = K.fullPivLu().solve(rhs);
    KktSolution s;
    s.qdd = x.head(n_);
    s.nu = x.tail(nc);
    s.cond = 1;
    return s;
  }
  // Every direction on one link (the chain's tip, say).
  KktSolution kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                  const std::string& link, const Mat& alpha, const Vec& beta) const {
    return kkt(q, qd, tau, ext, std::vector<std::string>(static_cast<std::size_t>(alpha.cols()), link), alpha, beta);
  }

  // The constraints the solver's documented pivot policy keeps (generator/solver/
  // constraint_multipliers.hpp; a policy rather than dynamics): LDL^T of E with diagonal
  // pivoting, each step taking the remaining direction with the largest ratio of its Schur-
  // complement diagonal to its own diagonal E_jj, a pivot <= tolerance * E_jj dropped.
  // Returns the indices of the kept constraints in pivot order.
  static std::vector<Eigen::Index> kept_constraints(const Mat& E, Scalar tolerance) {
    const Eigen::Index nc = E.rows();
    std::vector<Eigen::Index> kept;
    std::vector<bool> done(nc, false);
    for (Eigen::Index step = 0; step < nc; ++step) {
      // Schur-complement diagonal of every remaining direction over the kept set.
      const Eigen::Index m = static_cast<Eigen::Index>(kept.size());
      Mat EKK(m, m);
      for (Eigen::Index a = 0; a < m; ++a)
        for (Eigen::Index b = 0; b < m; ++b) EKK(a, b) = E(kept[a], kept[b]);
      const Eigen::LDLT<Mat> factor(EKK);
      Eigen::Index best = -1;
      Scalar best_ratio = Scalar(0), best_pivot = Scalar(0);
      for (Eigen::Index k = 0; k < nc; ++k) {
        if (done[k]) continue;
        Scalar pivot = E(k, k);
        if (m > 0) {
          Vec EKk(m);
          for (Eigen::Index a = 0; a < m; ++a) EKk[a] = E(kept[a], k);
          pivot -= EKk.dot(factor.solve(EKk));
        }
        const Scalar ratio = E(k, k) > Scalar(0) ? pivot / E(k, k) : Scalar(0);
        if (best < 0 || ratio > best_ratio) {
          best = k;
          best_ratio = ratio;
          best_pivot = pivot;
        }
      }
      done[best] = true;
      if (best_pivot > tolerance * E(best, best)) kept.push_back(best);
    }
    return kept;
  }

  // λmax/λmin of a symmetric PSD matrix (1 if empty, +inf if singular).
  static Scalar condition(const Mat& E) {
    if (E.rows() == 0) return Scalar(1);
    const Vec lambda = Eigen::SelfAdjointEigenSolver<Mat>(E, Eigen::EigenvaluesOnly).eigenvalues();
    if (!(lambda[0] > Scalar(0))) return std::numeric_limits<Scalar>::infinity();
    return lambda[lambda.size() - 1] / lambda[0];
  }

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

}  // namespace sweepgen::oracle
