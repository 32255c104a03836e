// DenseDynamics's members (oracle/dense_dynamics.hpp says what each computes and in which
// conventions), included only by the files that instantiate them, one per scalar:
// dense_dynamics_double.cpp (the report, the tests, bench/) and dense_dynamics_long_double.cpp (the
// tests). Apart, the two compile side by side, and the report's build compiles only the first.
#pragma once

#include "oracle/dense_dynamics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace sweepgen::oracle {

template <class Scalar>
DenseDynamics<Scalar>::DenseDynamics(const model::Chain& chain, const model::Vec3& gravity)
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

template <class Scalar>
auto DenseDynamics<Scalar>::in_solver_coordinates(const Vec& q, const Vec& qd, const Vec& qdd) const -> Vec {
  Vec out = qdd;
  if (root_body_ == 0) return out;
  const BodyMotion root = body_motion(q, qd, qdd)[root_body_];
  const M3 Rt = root.pose.R.transpose();
  const V3 omega = Rt * root.omega;
  out.head(3) = Rt * root.omega_dot;
  out.segment(3, 3) = Rt * (root.acceleration + gravity_) - omega.cross(Rt * root.velocity);
  return out;
}

template <class Scalar>
auto DenseDynamics<Scalar>::body_poses(const Vec& q) const -> std::vector<Pose> {
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

template <class Scalar>
auto DenseDynamics<Scalar>::link_pose(const Vec& q, const std::string& link) const -> Pose {
  const LinkData& l = links_.at(link);
  const Pose body = body_poses(q)[l.body];
  return {body.R * l.rotation, body.p + body.R * l.offset};
}

template <class Scalar>
auto DenseDynamics<Scalar>::body_motion(const Vec& q, const Vec& qd, const Vec& qdd, bool with_gravity) const -> std::vector<BodyMotion> {
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

template <class Scalar>
auto DenseDynamics<Scalar>::inverse_dynamics(const Vec& q, const Vec& qd, const Vec& qdd, const std::vector<ExternalWrench>& ext,
                     bool with_gravity) const -> Vec {
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

template <class Scalar>
auto DenseDynamics<Scalar>::mass_matrix(const Vec& q) const -> Mat {
  Mat M(n_, n_);
  const Vec zero = Vec::Zero(n_);
  for (std::size_t k = 0; k < n_; ++k) M.col(k) = inverse_dynamics(q, zero, Vec::Unit(n_, k), {}, false);
  return M;
}

template <class Scalar>
auto DenseDynamics<Scalar>::jacobian(const Vec& q, const std::string& link) const -> Jacobian {
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

template <class Scalar>
auto DenseDynamics<Scalar>::twist(const Vec& q, const Vec& qd, const std::string& link) const -> Six {
  const LinkData& l = links_.at(link);
  const BodyMotion b = body_motion(q, qd, Vec::Zero(n_), false)[l.body];
  const Pose L = frame_pose(b.pose, l);
  Six t;
  t << L.R.transpose() * b.omega, L.R.transpose() * (b.velocity + b.omega.cross(b.pose.R * l.offset));
  return t;
}

template <class Scalar>
auto DenseDynamics<Scalar>::spatial_acceleration(const Vec& q, const Vec& qd, const Vec& qdd, const std::string& link) const -> Six {
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

template <class Scalar>
auto DenseDynamics<Scalar>::drift(const Vec& q, const Vec& qd, const std::string& link) const -> Six {
  return spatial_acceleration(q, qd, Vec::Zero(n_), link);
}

template <class Scalar>
auto DenseDynamics<Scalar>::external_torque(const Vec& q, const std::vector<ExternalWrench>& ext) const -> Vec {
  Vec tau = Vec::Zero(n_);
  for (const ExternalWrench& e : ext) tau += jacobian(q, e.link).transpose() * e.wrench;
  return tau;
}

template <class Scalar>
auto DenseDynamics<Scalar>::forward_dynamics(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext) const -> Vec {
  return mass_matrix(q).fullPivLu().solve(tau + external_torque(q, ext) - bias(q, qd));
}

template <class Scalar>
auto DenseDynamics<Scalar>::constraint_jacobian(const Vec& q, const std::vector<std::string>& links, const Mat& alpha) const -> Mat {
  Mat Jc(alpha.cols(), static_cast<Eigen::Index>(n_));
  for (Eigen::Index k = 0; k < alpha.cols(); ++k)
    Jc.row(k) = alpha.col(k).transpose() * jacobian(q, links.at(static_cast<std::size_t>(k)));
  return Jc;
}

template <class Scalar>
auto DenseDynamics<Scalar>::constraint_drift(const Vec& q, const Vec& qd, const std::vector<std::string>& links, const Mat& alpha) const -> Vec {
  Vec c(alpha.cols());
  for (Eigen::Index k = 0; k < alpha.cols(); ++k)
    c[k] = alpha.col(k).dot(drift(q, qd, links.at(static_cast<std::size_t>(k))));
  return c;
}

template <class Scalar>
auto DenseDynamics<Scalar>::kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const -> KktSolution {
  KktSolution s = solve_kkt(q, qd, tau, ext, links, alpha, beta);
  const Mat Jc = constraint_jacobian(q, links, alpha);
  s.E = constraint_energy(mass_matrix(q), Jc);
  s.cond = condition(s.E);
  return s;
}

template <class Scalar>
auto DenseDynamics<Scalar>::solve_kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                      const std::vector<std::string>& links, const Mat& alpha, const Vec& beta) const -> KktSolution {
  return solve_rows(q, qd, tau + external_torque(q, ext), constraint_jacobian(q, links, alpha),
                    beta - constraint_drift(q, qd, links, alpha));
}

template <class Scalar>
auto DenseDynamics<Scalar>::solve_rows(const Vec& q, const Vec& qd, const Vec& tau, const Mat& Jc, const Vec& rhs) const
    -> KktSolution {
  const Eigen::Index nc = Jc.rows();
  Mat K = Mat::Zero(n_ + nc, n_ + nc);
  K.topLeftCorner(n_, n_) = mass_matrix(q);
  K.topRightCorner(n_, nc) = -Jc.transpose();
  K.bottomLeftCorner(nc, n_) = Jc;
  Vec b(n_ + nc);
  b.head(n_) = tau - bias(q, qd);
  b.tail(nc) = rhs;
  const Vec x = K.fullPivLu().solve(b);
  KktSolution s;
  s.qdd = x.head(n_);
  s.nu = x.tail(nc);
  s.cond = 1;
  return s;
}

template <class Scalar>
auto DenseDynamics<Scalar>::potential_energy(const Vec& q) const -> Scalar {
  const std::vector<Pose> poses = body_poses(q);
  Scalar potential = 0;
  for (std::size_t i = 1; i < poses.size(); ++i)
    potential -= gravity_.dot(bodies_[i].mass * poses[i].p + poses[i].R * bodies_[i].first_moment);
  return potential;
}

template <class Scalar>
auto DenseDynamics<Scalar>::coupling_rows(const model::Chain& chain) -> Mat {
  const auto column = [&](const std::string& joint) {
    for (std::size_t i = 1; i < chain.joints.size(); ++i)
      if (chain.joints[i].name == joint) return static_cast<Eigen::Index>(i - 1);
    return Eigen::Index(-1);  // locked or off the chain
  };
  std::vector<std::pair<Eigen::Index, Eigen::Index>> pairs;
  std::vector<Scalar> ratios;
  for (const model::MimicJoint& mimic : chain.mimics) {
    const Eigen::Index m = column(mimic.joint), s = column(mimic.source);
    if (m < 0 || s < 0) continue;
    pairs.emplace_back(m, s);
    ratios.push_back(Scalar(mimic.multiplier));
  }
  Mat rows = Mat::Zero(static_cast<Eigen::Index>(pairs.size()), static_cast<Eigen::Index>(chain.dof()));
  for (std::size_t r = 0; r < pairs.size(); ++r) {  // (M1)
    rows(static_cast<Eigen::Index>(r), pairs[r].first) += Scalar(1);
    rows(static_cast<Eigen::Index>(r), pairs[r].second) -= ratios[r];
  }
  return rows;
}

// A motion vector [ω; v] of coordinates C in those of a frame at pose (R, p) in C (F1):
// [R^T ω; R^T (v + ω × p)].
template <class Scalar>
Eigen::Matrix<Scalar, 6, 6> motion_into(const Eigen::Matrix<Scalar, 3, 3>& R, const Eigen::Matrix<Scalar, 3, 1>& p) {
  Eigen::Matrix<Scalar, 3, 3> p_cross;
  p_cross << Scalar(0), -p[2], p[1], p[2], Scalar(0), -p[0], -p[1], p[0], Scalar(0);
  Eigen::Matrix<Scalar, 6, 6> X = Eigen::Matrix<Scalar, 6, 6>::Zero();
  X.template topLeftCorner<3, 3>() = R.transpose();
  X.template bottomRightCorner<3, 3>() = R.transpose();
  X.template bottomLeftCorner<3, 3>() = -R.transpose() * p_cross;
  return X;
}

template <class Scalar>
auto DenseDynamics<Scalar>::attached_pose(const Vec& q, const AttachedFrame& frame) const -> Pose {
  const Pose link = link_pose(q, frame.link);
  return {link.R * frame.R, link.p + link.R * frame.p};
}

template <class Scalar>
auto DenseDynamics<Scalar>::relative_motion(const Vec& q, const Vec& qd, const AttachedFrame& A,
                                            const AttachedFrame& B) const -> RelativeMotion {
  // Each frame's Jacobian, twist and drift from its link's, through the constant attachment.
  const auto of = [&](const AttachedFrame& f) {
    const Eigen::Matrix<Scalar, 6, 6> X = motion_into<Scalar>(f.R, f.p);
    return std::tuple<Jacobian, Six, Six>{X * jacobian(q, f.link), X * twist(q, qd, f.link), X * drift(q, qd, f.link)};
  };
  const auto [J_A, v_A, c_A] = of(A);
  const auto [J_B, v_B, c_B] = of(B);
  // ^A X_B: B's coordinates into A's, A's pose in B's coordinates being (R_B^T R_A, R_B^T (p_A − p_B)).
  const Pose world_A = attached_pose(q, A), world_B = attached_pose(q, B);
  const Eigen::Matrix<Scalar, 6, 6> A_X_B =
      motion_into<Scalar>(world_B.R.transpose() * world_A.R, world_B.R.transpose() * (world_A.p - world_B.p));
  const Six w = A_X_B * v_B;  // B's twist in A's coordinates
  Six product;                // v_A × ^A X_B v_B, the spatial cross product of motions (L1)
  product << v_A.template head<3>().cross(w.template head<3>()),
      v_A.template head<3>().cross(w.template tail<3>()) + v_A.template tail<3>().cross(w.template head<3>());
  RelativeMotion r;
  r.J = J_A - A_X_B * J_B;        // (L2)
  r.velocity = v_A - w;           // (L1)
  r.drift = c_A - A_X_B * c_B + product;  // (L2)
  return r;
}

template <class Scalar>
auto DenseDynamics<Scalar>::pose_error(const Vec& q, const AttachedFrame& A, const AttachedFrame& B) const -> Six {
  const Pose world_A = attached_pose(q, A), world_B = attached_pose(q, B);
  const Eigen::AngleAxis<Scalar> turn(M3(world_B.R.transpose() * world_A.R));
  Six e;  // (L3)
  e << turn.angle() * turn.axis(), world_A.R.transpose() * (world_A.p - world_B.p);
  return e;
}

template <class Scalar>
auto DenseDynamics<Scalar>::kkt(const Vec& q, const Vec& qd, const Vec& tau, const std::vector<ExternalWrench>& ext,
                const std::string& link, const Mat& alpha, const Vec& beta) const -> KktSolution {
  return kkt(q, qd, tau, ext, std::vector<std::string>(static_cast<std::size_t>(alpha.cols()), link), alpha, beta);
}

template <class Scalar>
auto DenseDynamics<Scalar>::kept_constraints(const Mat& E, Scalar tolerance) -> std::vector<Eigen::Index> {
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

template <class Scalar>
auto DenseDynamics<Scalar>::constraint_energy(const Mat& M, const Mat& J) -> Mat {
  if (J.rows() == 0) return Mat(0, 0);
  return J * M.ldlt().solve(J.transpose());
}

template <class Scalar>
auto DenseDynamics<Scalar>::condition(const Mat& E) -> Scalar {
  if (E.rows() == 0) return Scalar(1);
  const Vec lambda = Eigen::SelfAdjointEigenSolver<Mat>(E, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(lambda[0] > Scalar(0))) return std::numeric_limits<Scalar>::infinity();
  return lambda[lambda.size() - 1] / lambda[0];
}

}  // namespace sweepgen::oracle
