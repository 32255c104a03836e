// Spatial vector algebra (Featherstone, "Rigid Body Dynamics Algorithms", 2008, ch. 2),
// templated on the scalar so that the same code runs in double, long double, float and in
// the generator's symbolic scalar.
//
// Conventions (docs/derivation.md, "Frames"):
//   motion vectors  [angular; linear]      force vectors [moment; force]
//   Transform{E, r} is the motion transform  B_X_A  from frame A to frame B:
//       E  rotates A coordinates into B coordinates,
//       r  is the origin of B expressed in A coordinates,
//       B_X_A = [ E , 0 ; -E r× , E ].
//   Its transpose maps forces from B back to A.
// Everything here is allocation-free and branch-free, so a symbolic scalar can trace it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace sweepgen::spatial {

template <class Scalar> using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
template <class Scalar> using Mat3 = Eigen::Matrix<Scalar, 3, 3>;

template <class Scalar>
Mat3<Scalar> skew(const Vec3<Scalar>& v) {
  Mat3<Scalar> m;
  m << Scalar(0), -v.z(), v.y(),  //
      v.z(), Scalar(0), -v.x(),   //
      -v.y(), v.x(), Scalar(0);
  return m;
}

// Copies the upper triangle onto the lower one. After every update of a symmetric block
// this keeps the matrix exactly symmetric in floating point, and lets the tracer drop the
// lower triangle's arithmetic as dead code.
template <class Scalar>
void symmetrize_from_upper(Mat3<Scalar>& m) {
  m(1, 0) = m(0, 1);
  m(2, 0) = m(0, 2);
  m(2, 1) = m(1, 2);
}

template <class Scalar>
struct Motion {
  Vec3<Scalar> angular = Vec3<Scalar>::Zero();
  Vec3<Scalar> linear = Vec3<Scalar>::Zero();

  static Motion zero() { return {}; }
  Motion operator+(const Motion& o) const { return {angular + o.angular, linear + o.linear}; }
  Motion operator-(const Motion& o) const { return {angular - o.angular, linear - o.linear}; }
  Motion operator*(const Scalar& s) const { return {angular * s, linear * s}; }
  Motion& operator+=(const Motion& o) {
    angular += o.angular;
    linear += o.linear;
    return *this;
  }
};

template <class Scalar>
struct Force {
  Vec3<Scalar> moment = Vec3<Scalar>::Zero();
  Vec3<Scalar> force = Vec3<Scalar>::Zero();

  static Force zero() { return {}; }
  Force operator+(const Force& o) const { return {moment + o.moment, force + o.force}; }
  Force operator-(const Force& o) const { return {moment - o.moment, force - o.force}; }
  Force operator-() const { return {-moment, -force}; }
  Force operator*(const Scalar& s) const { return {moment * s, force * s}; }
  Force& operator+=(const Force& o) {
    moment += o.moment;
    force += o.force;
    return *this;
  }
  Force& operator-=(const Force& o) {
    moment -= o.moment;
    force -= o.force;
    return *this;
  }
};

// Power pairing  f · v  (force times motion).
template <class Scalar>
Scalar dot(const Force<Scalar>& f, const Motion<Scalar>& v) {
  return f.moment.dot(v.angular) + f.force.dot(v.linear);
}

// Spatial motion cross product  v × m  (Featherstone eq. 2.31).
template <class Scalar>
Motion<Scalar> cross_motion(const Motion<Scalar>& v, const Motion<Scalar>& m) {
  return {v.angular.cross(m.angular), v.angular.cross(m.linear) + v.linear.cross(m.angular)};
}

// Spatial force cross product  v ×* f  (Featherstone eq. 2.32).
template <class Scalar>
Force<Scalar> cross_force(const Motion<Scalar>& v, const Force<Scalar>& f) {
  return {v.angular.cross(f.moment) + v.linear.cross(f.force), v.angular.cross(f.force)};
}

// The four maps of a transform {E, r} (B_X_A, below), written once for Transform and for its
// specialisation that differentiates a joint's transform (solver/joint_transform_tangent.hpp).
// B_X_A v
template <class Scalar>
Motion<Scalar> motion_to_b(const Mat3<Scalar>& E, const Vec3<Scalar>& r, const Motion<Scalar>& v) {
  return {E * v.angular, E * (v.linear - r.cross(v.angular))};
}
// (B_X_A)^-1 v : motion from B back to A.
template <class Scalar>
Motion<Scalar> motion_to_a(const Mat3<Scalar>& E, const Vec3<Scalar>& r, const Motion<Scalar>& v) {
  const Vec3<Scalar> angular = E.transpose() * v.angular;
  return {angular, E.transpose() * v.linear + r.cross(angular)};
}
// (B_X_A)^T f : force from B back to A.
template <class Scalar>
Force<Scalar> force_to_a(const Mat3<Scalar>& E, const Vec3<Scalar>& r, const Force<Scalar>& f) {
  const Vec3<Scalar> force = E.transpose() * f.force;
  return {E.transpose() * f.moment + r.cross(force), force};
}
// B_X_A^-T f = B_X*_A f : force from A to B.
template <class Scalar>
Force<Scalar> force_to_b(const Mat3<Scalar>& E, const Vec3<Scalar>& r, const Force<Scalar>& f) {
  return {E * (f.moment - r.cross(f.force)), E * f.force};
}

template <class Scalar>
struct Transform {
  Mat3<Scalar> E = Mat3<Scalar>::Identity();
  Vec3<Scalar> r = Vec3<Scalar>::Zero();

  static Transform identity() { return {}; }

  template <class Other>
  Transform<Other> cast() const {
    return {E.template cast<Other>(), r.template cast<Other>()};
  }

  Motion<Scalar> apply(const Motion<Scalar>& v) const { return motion_to_b(E, r, v); }
  Motion<Scalar> apply_inverse(const Motion<Scalar>& v) const { return motion_to_a(E, r, v); }
  Force<Scalar> apply_transpose(const Force<Scalar>& f) const { return force_to_a(E, r, f); }
  Force<Scalar> apply_force(const Force<Scalar>& f) const { return force_to_b(E, r, f); }
};

// ^AX_B from ^BX_A: E^T, and the origin of A in B's coordinates, −E r.
template <class Scalar>
Transform<Scalar> inverse(const Transform<Scalar>& b_x_a) {
  Transform<Scalar> a_x_b;
  a_x_b.E = b_x_a.E.transpose();
  a_x_b.r = -(b_x_a.E * b_x_a.r);
  return a_x_b;
}

// Composition  C_X_A = C_X_B * B_X_A (docs/derivation.md, (F1)).
template <class Scalar>
Transform<Scalar> operator*(const Transform<Scalar>& c_x_b, const Transform<Scalar>& b_x_a) {
  return {c_x_b.E * b_x_a.E, b_x_a.r + b_x_a.E.transpose() * c_x_b.r};
}

// Symmetric 6x6 inertia in blocks  [ A  B ; B^T  C ]  acting on [angular; linear]:
// rigid-body inertias (A = Ī about the frame origin, B = h×, C = m 1) and articulated-body
// inertias alike. A and C are kept exactly symmetric.
template <class Scalar>
struct Inertia {
  Mat3<Scalar> A = Mat3<Scalar>::Zero();
  Mat3<Scalar> B = Mat3<Scalar>::Zero();
  Mat3<Scalar> C = Mat3<Scalar>::Zero();

  // Rigid body of mass m, first moment h = m c, rotational inertia Ī about the origin.
  static Inertia rigid(const Scalar& mass, const Vec3<Scalar>& h, const Mat3<Scalar>& inertia_origin) {
    Inertia I;
    I.A = inertia_origin;
    I.B = skew(h);
    I.C = Mat3<Scalar>::Identity() * mass;
    return I;
  }

  template <class Other>
  Inertia<Other> cast() const {
    return {A.template cast<Other>(), B.template cast<Other>(), C.template cast<Other>()};
  }

  Force<Scalar> operator*(const Motion<Scalar>& v) const {
    return {A * v.angular + B * v.linear, B.transpose() * v.angular + C * v.linear};
  }
  Inertia operator+(const Inertia& o) const { return {A + o.A, B + o.B, C + o.C}; }

  // this − U U^T / D  with U a force-like column (the articulated-body projection, eq. 7.41).
  Inertia minus_outer(const Force<Scalar>& U, const Scalar& inverse_D) const {
    Inertia I;
    const Vec3<Scalar> Un = U.moment * inverse_D;
    const Vec3<Scalar> Uf = U.force * inverse_D;
    I.A = A - Un * U.moment.transpose();
    I.B = B - Un * U.force.transpose();
    I.C = C - Uf * U.force.transpose();
    symmetrize_from_upper(I.A);
    symmetrize_from_upper(I.C);
    return I;
  }

  // The same for a rigid-body inertia (B = h×, C = m 1), in its ten parameters: with
  // h' = Eᵀ h + (m/2) r,  A'' = Eᵀ A E − (r h'ᵀ + h' rᵀ) + 2 (h'·r) 1,  h'' = Eᵀ h + m r,  m'' = m
  // (the block form above with B' = (Eᵀ h)×, C' = m 1 and r× s× + s× r× = r sᵀ + s rᵀ − 2 (r·s) 1).
  Inertia rigid_transformed_to_parent(const Transform<Scalar>& X) const {
    const Scalar& m = C(0, 0);
    const Vec3<Scalar> h_rotated = X.E.transpose() * Vec3<Scalar>(B(2, 1), B(0, 2), B(1, 0));
    const Vec3<Scalar> h_half = h_rotated + X.r * (m * Scalar(0.5));
    Mat3<Scalar> A1 = X.E.transpose() * A * X.E;
    A1 -= X.r * h_half.transpose() + h_half * X.r.transpose();
    A1.diagonal().array() += Scalar(2) * h_half.dot(X.r);
    symmetrize_from_upper(A1);
    return rigid(m, Vec3<Scalar>(h_rotated + X.r * m), A1);
  }

  // (B_X_A)^T I (B_X_A): an inertia given in frame B expressed in frame A (F1; Featherstone eq. 2.66), in the
  // block form  A'' = A' − B' r× + r× B'^T − r× C' r×,  B'' = B' + r× C',  C'' = C'
  // with A' = E^T A E, B' = E^T B E, C' = E^T C E.
  Inertia transformed_to_parent(const Transform<Scalar>& X) const {
    Mat3<Scalar> A1 = X.E.transpose() * A * X.E;
    const Mat3<Scalar> B1 = X.E.transpose() * B * X.E;
    Mat3<Scalar> C1 = X.E.transpose() * C * X.E;
    symmetrize_from_upper(A1);
    symmetrize_from_upper(C1);
    const Mat3<Scalar> rx = skew(X.r);
    const Mat3<Scalar> rxC = rx * C1;
    Inertia I;
    I.A = A1 - B1 * rx + rx * B1.transpose() - rxC * rx;
    I.B = B1 + rxC;
    I.C = C1;
    symmetrize_from_upper(I.A);
    return I;
  }
};

}  // namespace sweepgen::spatial
