// The tangent of a joint's transform where it is applied (docs/derivation.md, (D6)). With S_i
// constant in body i's frame, X_i = X_J(q_i) X_T,i (F2) has ∂X_i/∂q_i = −(S_i×) X_i, so
//   d(X v)   = X dv − S × (X v) dq,        d(Xᵀ f)  = Xᵀ (df + S ×* f dq),
//   d(X⁻¹ v) = X⁻¹ (dv + S × v dq),        d(X* f)  = X* df − S ×* (X* f) dq,
// where X acts with its values only. The product rule (D1) through X's entries spends a
// transform's multiplications per vector and column on the first term of each; with a constant
// S the cross products fold to sign flips of values already computed. The same derivative of
// the same arithmetic, rounded otherwise.
//
// Transform<Dual<T>> is Transform with that rule: JointModel::transform records S_i and q_i's
// tangent (with_joint_tangent); E and r keep their own tangents (D1) for every other use, and a
// Transform without a record (a composition, a fixed frame) applies by (D1).
#pragma once

#include <algorithm>

#include "solver/dual_scalar.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::spatial {

template <class T>
struct Transform<solver::Dual<T>> {
  using D = solver::Dual<T>;

  Mat3<D> E = Mat3<D>::Identity();
  Vec3<D> r = Vec3<D>::Zero();
  // (D6)'s record: the joint's S in this (the child's) frame and q's tangent; dq empty: none.
  Motion<D> S{};
  typename D::Tangent dq{};

  static Transform identity() { return {}; }

  template <class Other>
  Transform<Other> cast() const {
    return {E.template cast<Other>(), r.template cast<Other>()};
  }

  Motion<D> apply(const Motion<D>& v) const {
    if (dq.empty()) return motion_to_b(E, r, v);
    const Motion<D> moved = motion_to_b(values(E), values(r), v);
    return along(moved, cross_motion(values_of(S), values_of(moved)), true);
  }
  Motion<D> apply_inverse(const Motion<D>& v) const {
    if (dq.empty()) return motion_to_a(E, r, v);
    return motion_to_a(values(E), values(r), along(v, cross_motion(values_of(S), values_of(v)), false));
  }
  Force<D> apply_transpose(const Force<D>& f) const {
    if (dq.empty()) return force_to_a(E, r, f);
    return force_to_a(values(E), values(r), along(f, cross_force(values_of(S), values_of(f)), false));
  }
  Force<D> apply_force(const Force<D>& f) const {
    if (dq.empty()) return force_to_b(E, r, f);
    const Force<D> moved = force_to_b(values(E), values(r), f);
    return along(moved, cross_force(values_of(S), values_of(moved)), true);
  }

 private:
  // X's entries with their values only (no tangent).
  template <class Matrix>
  static Matrix values(const Matrix& x) {
    return x.unaryExpr([](const D& e) { return D(e.value()); });
  }
  static Vec3<T> values_of(const Vec3<D>& x) { return {x[0].value(), x[1].value(), x[2].value()}; }
  static Motion<T> values_of(const Motion<D>& m) { return {values_of(m.angular), values_of(m.linear)}; }
  static Force<T> values_of(const Force<D>& f) { return {values_of(f.moment), values_of(f.force)}; }
  // x with tangent dx + c dq, or dx − c dq (c a value).
  D along(const D& x, const T& c, bool minus) const {
    typename D::Tangent tangent(std::max(x.tangent().size(), dq.size()), T(0));
    for (std::size_t j = 0; j < tangent.size(); ++j) {
      if (j >= dq.size()) {
        tangent[j] = x.derivative(j);
        continue;
      }
      const T step = c * dq[j];
      tangent[j] = minus ? x.derivative(j) - step : x.derivative(j) + step;
    }
    return D(x.value(), std::move(tangent));
  }
  Vec3<D> along(const Vec3<D>& x, const Vec3<T>& c, bool minus) const {
    return {along(x[0], c[0], minus), along(x[1], c[1], minus), along(x[2], c[2], minus)};
  }
  Motion<D> along(const Motion<D>& x, const Motion<T>& c, bool minus) const {
    return {along(x.angular, c.angular, minus), along(x.linear, c.linear, minus)};
  }
  Force<D> along(const Force<D>& x, const Force<T>& c, bool minus) const {
    return {along(x.moment, c.moment, minus), along(x.force, c.force, minus)};
  }
};

}  // namespace sweepgen::spatial

namespace sweepgen::solver {

// JointModel::transform's record for (D6): nothing for a scalar without tangents.
template <class Scalar>
spatial::Transform<Scalar> with_joint_tangent(spatial::Transform<Scalar> X, const spatial::Motion<Scalar>&,
                                              const Scalar&) {
  return X;
}
template <class T>
spatial::Transform<Dual<T>> with_joint_tangent(spatial::Transform<Dual<T>> X, const spatial::Motion<Dual<T>>& S,
                                               const Dual<T>& q) {
  X.S = S;
  X.dq = q.tangent();
  return X;
}

}  // namespace sweepgen::solver
