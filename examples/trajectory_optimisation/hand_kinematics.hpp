// The Panda hand's pose and velocity in the base frame, and their exact derivatives.
//
// The generated solver returns q̈ and ν and their Jacobians; the hand's height over the plane, its
// normal velocity and the plane's normal in the hand frame (the constraint direction alpha) are the
// example's own functions of (q, q̇). They are written once, templated on the scalar: with double
// for the constraint values, with Dual (forward mode, one tangent per q and q̇ coordinate) for
// their exact Jacobian. The chain is robots/panda/panda.urdf's, joint by joint:
//   R_i = R_{i-1} Rx(roll_i) Rz(q_i),  p_i = p_{i-1} + R_{i-1} xyz_i,
// then the fixed joints panda_joint8 (0.107 m along z) and panda_hand_joint (Rz(-pi/4)), and
//   ṗ = Σ z_i × (p − o_i) q̇_i,  ω = Σ z_i q̇_i   (z_i, o_i: joint i's axis and origin in the base frame).
// A copy for another robot replaces kJoints and the hand's offset with its URDF's origins.
// tests/test_trajectory_kinematics.cpp holds these to the project's reading of panda.urdf.
#pragma once

#include <array>
#include <cmath>

namespace trajopt {

constexpr int kDof = 7;
constexpr int kTangents = 2 * kDof;  // d/dq, d/dq̇

// A value and its derivatives along kTangents seeded coordinates (forward mode).
struct Dual {
  double v = 0;
  std::array<double, kTangents> d{};
  Dual() = default;
  Dual(double value) : v(value) {}  // a constant: every derivative 0
};
inline Dual operator+(const Dual& a, const Dual& b) {
  Dual r(a.v + b.v);
  for (int k = 0; k < kTangents; ++k) r.d[k] = a.d[k] + b.d[k];
  return r;
}
inline Dual operator-(const Dual& a, const Dual& b) {
  Dual r(a.v - b.v);
  for (int k = 0; k < kTangents; ++k) r.d[k] = a.d[k] - b.d[k];
  return r;
}
inline Dual operator-(const Dual& a) { return Dual(0.0) - a; }
inline Dual operator*(const Dual& a, const Dual& b) {
  Dual r(a.v * b.v);
  for (int k = 0; k < kTangents; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}
inline Dual sin(const Dual& a) {
  Dual r(std::sin(a.v));
  const double c = std::cos(a.v);
  for (int k = 0; k < kTangents; ++k) r.d[k] = c * a.d[k];
  return r;
}
inline Dual cos(const Dual& a) {
  Dual r(std::cos(a.v));
  const double s = -std::sin(a.v);
  for (int k = 0; k < kTangents; ++k) r.d[k] = s * a.d[k];
  return r;
}
// The double overloads, which unqualified calls in this namespace would otherwise take as Dual's.
inline double sin(double x) { return std::sin(x); }
inline double cos(double x) { return std::cos(x); }

template <class T>
using Vec3 = std::array<T, 3>;
template <class T>
using Mat3 = std::array<T, 9>;  // row-major

// The hand in the base frame at (q, q̇).
template <class T>
struct HandState {
  Vec3<T> p;      // panda_hand's origin [m]
  Mat3<T> R;      // base_R_hand
  Vec3<T> pd;     // ṗ [m/s]
  Vec3<T> omega;  // ω [rad/s]
};

// Joint i's origin in its parent's frame (panda.urdf): xyz, and roll (each 0 or ±pi/2, taken as the
// exact quarter turn, as the generator's quarter-turn rule takes it).
struct JointOrigin {
  double x, y, z;
  int roll_quarter_turns;  // roll = roll_quarter_turns * pi/2
};
constexpr JointOrigin kJoints[kDof] = {
    {0, 0, 0.333, 0},   {0, 0, 0, -1},      {0, -0.316, 0, 1}, {0.0825, 0, 0, 1},
    {-0.0825, 0.384, 0, -1}, {0, 0, 0, 1}, {0.088, 0, 0, 1},
};
constexpr double kFlangeToHand = 0.107;  // panda_joint8: z offset [m]
constexpr double kHandYaw = -0.7853981633974483;  // panda_hand_joint: rpy="0 0 -pi/4"

template <class T>
Vec3<T> mul(const Mat3<T>& R, const Vec3<T>& v) {
  return {R[0] * v[0] + R[1] * v[1] + R[2] * v[2], R[3] * v[0] + R[4] * v[1] + R[5] * v[2],
          R[6] * v[0] + R[7] * v[1] + R[8] * v[2]};
}
template <class T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
// R Rz(angle) from c = cos(angle), s = sin(angle): columns 0 and 1 turn, column 2 stays.
template <class T, class C>
Mat3<T> turn_z(const Mat3<T>& R, const C& c, const C& s) {
  Mat3<T> r = R;
  for (int row = 0; row < 3; ++row) {
    r[3 * row] = R[3 * row] * c + R[3 * row + 1] * s;
    r[3 * row + 1] = R[3 * row + 1] * c - R[3 * row] * s;
  }
  return r;
}
// R Rx(k pi/2), k in {-1, 0, 1}: exact column swaps (Rx(pi/2) = [1 0 0; 0 0 -1; 0 1 0]).
template <class T>
Mat3<T> turn_x_quarter(const Mat3<T>& R, int k) {
  if (k == 0) return R;
  Mat3<T> r = R;
  for (int row = 0; row < 3; ++row) {
    const T c1 = R[3 * row + 1], c2 = R[3 * row + 2];
    r[3 * row + 1] = k > 0 ? c2 : -c2;
    r[3 * row + 2] = k > 0 ? -c1 : c1;
  }
  return r;
}

template <class T>
HandState<T> hand_state(const T* q, const T* qd) {
  Mat3<T> R = {T(1.0), T(0.0), T(0.0), T(0.0), T(1.0), T(0.0), T(0.0), T(0.0), T(1.0)};
  Vec3<T> p = {T(0.0), T(0.0), T(0.0)};
  Vec3<T> axis[kDof], origin[kDof];
  for (int i = 0; i < kDof; ++i) {
    const Vec3<T> offset = mul(R, Vec3<T>{T(kJoints[i].x), T(kJoints[i].y), T(kJoints[i].z)});
    for (int a = 0; a < 3; ++a) p[a] = p[a] + offset[a];
    R = turn_x_quarter(R, kJoints[i].roll_quarter_turns);
    axis[i] = {R[2], R[5], R[8]};
    origin[i] = p;
    R = turn_z(R, cos(q[i]), sin(q[i]));
  }
  for (int a = 0; a < 3; ++a) p[a] = p[a] + R[3 * a + 2] * T(kFlangeToHand);
  R = turn_z(R, std::cos(kHandYaw), std::sin(kHandYaw));
  HandState<T> hand{p, R, {T(0.0), T(0.0), T(0.0)}, {T(0.0), T(0.0), T(0.0)}};
  for (int i = 0; i < kDof; ++i) {
    const Vec3<T> lever = {p[0] - origin[i][0], p[1] - origin[i][1], p[2] - origin[i][2]};
    const Vec3<T> v = cross(axis[i], lever);
    for (int a = 0; a < 3; ++a) {
      hand.pd[a] = hand.pd[a] + v[a] * qd[i];
      hand.omega[a] = hand.omega[a] + axis[i][a] * qd[i];
    }
  }
  return hand;
}

// (q, q̇) as Dual, seeded: q_i along tangent i, q̇_i along tangent dof + i.
inline void seed(const double* q, const double* qd, Dual* q_dual, Dual* qd_dual) {
  for (int i = 0; i < kDof; ++i) {
    q_dual[i] = Dual(q[i]);
    q_dual[i].d[i] = 1;
    qd_dual[i] = Dual(qd[i]);
    qd_dual[i].d[kDof + i] = 1;
  }
}

}  // namespace trajopt
