// Translation between sweepgen's conventions and those of KDL's ChainHdSolver_Vereshchagin, in
// one place for `sweepgen report` (report/kdl_row.cpp) and tests/test_reference_kdl.cpp,
// which verifies every line of it against KDL itself (its header has the table):
//   sweepgen                                      KDL
//   motion [angular; linear], force [moment; force]  Twist(vel, rot), Wrench(force, torque)
//   F_ext on body i: link frame, about its origin    f_ext[i-1]: base orientation, same point
//   α_k: tip frame, [moment; force]                  alfa column k: [force; moment], base orientation
//   gravity g                                        root acceleration Twist(-g, 0)
// R_i is the rotation of body i's frame into the base frame (body_rotations).
// Only with KDL (SWEEPGEN_HAVE_KDL).
#pragma once

#ifdef SWEEPGEN_HAVE_KDL

#include <Eigen/Core>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <vector>

#include "solver/state.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::oracle {

inline KDL::Vector kdl_vector(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
inline Eigen::Vector3d from_kdl(const KDL::Vector& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }
inline Eigen::Matrix3d from_kdl(const KDL::Rotation& r) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
  return m;
}
inline KDL::JntArray kdl_joints(const Eigen::VectorXd& v) {
  KDL::JntArray a(static_cast<unsigned>(v.size()));
  a.data = v;
  return a;
}

// R_i, i = 0..N, from the outward sweep's X_i = {E_i, r_i}: R_i = R_{i-1} E_i^T.
inline std::vector<Eigen::Matrix3d> body_rotations(const solver::KinematicsState<double>& kin) {
  std::vector<Eigen::Matrix3d> R(kin.body.size(), Eigen::Matrix3d::Identity());
  for (std::size_t i = 1; i < kin.body.size(); ++i) R[i] = R[i - 1] * kin.body[i].X.E.transpose();
  return R;
}

// A wrench on body i (its frame, about its origin) as KDL's f_ext[i-1]: rotated, never shifted.
inline KDL::Wrench to_kdl_base(const spatial::Force<double>& f, const Eigen::Matrix3d& R_i) {
  return KDL::Wrench(kdl_vector(R_i * f.force), kdl_vector(R_i * f.moment));
}

// Constraint directions on body N (its frame, about its origin) as KDL's alfa.
inline KDL::Jacobian kdl_directions(const std::vector<spatial::Force<double>>& alpha, const Eigen::Matrix3d& R_N) {
  KDL::Jacobian alfa(static_cast<unsigned>(alpha.size()));
  for (std::size_t k = 0; k < alpha.size(); ++k) {
    alfa.data.block<3, 1>(0, static_cast<Eigen::Index>(k)) = R_N * alpha[k].force;
    alfa.data.block<3, 1>(3, static_cast<Eigen::Index>(k)) = R_N * alpha[k].moment;
  }
  return alfa;
}

// A KDL twist in base orientation as a sweepgen motion in the frame whose rotation is R.
inline spatial::Motion<double> from_kdl_base(const KDL::Twist& t, const Eigen::Matrix3d& R) {
  return {R.transpose() * from_kdl(t.rot), R.transpose() * from_kdl(t.vel)};
}

// KDL's root acceleration for gravity g: the base accelerating by -g (sweepgen's Ẍ_0 = -[0; g]).
inline KDL::Twist kdl_root_acceleration(const Eigen::Vector3d& gravity) {
  return KDL::Twist(kdl_vector(-gravity), KDL::Vector::Zero());
}

}  // namespace sweepgen::oracle

#endif  // SWEEPGEN_HAVE_KDL
