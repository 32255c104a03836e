// A forward-mode dual scalar (docs/derivation.md, (D1)): a value x and its tangent ẋ, the
// derivatives of x along m seeded input directions, carried through every operation by the
// chain rule. The templated reference sweeps run with it as they do with double, and return
// the solution together with its directional derivatives: exact derivatives of the arithmetic
// the solver performs (no differencing, no truncation error).
//
// The tangent is a vector of T, empty for a constant (all derivatives zero: the robot's folded
// constants, literals, tolerances cost nothing). T may be a floating-point type, Quad, or the
// symbolic Symbol: then the tangents are graph nodes, folded and shared like the values.
//
// The data-dependent steps (scalar_ops.hpp) differentiate their active branch, decided by the
// values: select_greater(a, b, x, y) = a > b ? x : y carries the chosen argument's tangent,
// minimum / maximum / abs_value likewise; equilibration_scale is piecewise constant (an exact
// power of two), its tangent 0. A dropped pivot or a locked joint (J1) is thereby differentiated
// as the solver returns it: that direction or joint stays out, as the status says.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "solver/scalar_ops.hpp"

namespace sweepgen::solver {

template <class T>
class Dual {
 public:
  using Tangent = std::vector<T>;

  Dual() : value_(0) {}
  Dual(const T& value) : value_(value) {}  // NOLINT: implicit, a constant (zero tangent)
  template <class U, std::enable_if_t<std::is_arithmetic_v<U> && !std::is_same_v<U, T>, int> = 0>
  Dual(U value) : value_(T(value)) {}  // NOLINT: literals mix as with double
  Dual(T value, Tangent tangent) : value_(std::move(value)), tangent_(std::move(tangent)) {}

  const T& value() const { return value_; }
  // Derivative along seeded direction j (0 beyond the stored ones).
  T derivative(std::size_t j) const { return j < tangent_.size() ? tangent_[j] : T(0); }
  const Tangent& tangent() const { return tangent_; }
  // To a built-in type: the value (explicit, as Quad's).
  template <class U, std::enable_if_t<std::is_arithmetic_v<U>, int> = 0>
  explicit operator U() const {
    return static_cast<U>(value_);
  }

  Dual& operator+=(const Dual& o) { return *this = *this + o; }
  Dual& operator-=(const Dual& o) { return *this = *this - o; }
  Dual& operator*=(const Dual& o) { return *this = *this * o; }
  Dual& operator/=(const Dual& o) { return *this = *this / o; }

  // d(a ± b) = da ± db
  friend Dual operator+(const Dual& a, const Dual& b) {
    return {a.value_ + b.value_, combine(a, b, [](const T& x, const T& y) { return x + y; })};
  }
  friend Dual operator-(const Dual& a, const Dual& b) {
    return {a.value_ - b.value_, combine(a, b, [](const T& x, const T& y) { return x - y; })};
  }
  friend Dual operator-(const Dual& a) { return {-a.value_, map(a, [](const T& x) { return -x; })}; }
  friend Dual operator+(const Dual& a) { return a; }
  // d(a b) = da b + a db
  friend Dual operator*(const Dual& a, const Dual& b) {
    const T& u = a.value_;
    const T& v = b.value_;
    return {u * v, combine(a, b, [&](const T& x, const T& y) { return x * v + u * y; })};
  }
  // d(a / b) = (da − (a/b) db) / b
  friend Dual operator/(const Dual& a, const Dual& b) {
    const T quotient = a.value_ / b.value_;
    const T& v = b.value_;
    return {quotient, combine(a, b, [&](const T& x, const T& y) { return (x - quotient * y) / v; })};
  }
  // d sin a = cos a da, d cos a = −sin a da
  friend Dual sin(const Dual& a) {
    using std::cos;
    using std::sin;
    const T c = cos(a.value_);
    return {sin(a.value_), map(a, [&](const T& x) { return c * x; })};
  }
  friend Dual cos(const Dual& a) {
    using std::cos;
    using std::sin;
    const T s = sin(a.value_);
    return {cos(a.value_), map(a, [&](const T& x) { return -(s * x); })};
  }
  // d sqrt a = da / (2 sqrt a), d atan2(y, x) = (x dy − y dx) / (x² + y²)
  friend Dual sqrt(const Dual& a) {
    using std::sqrt;
    const T root = sqrt(a.value_);
    return {root, map(a, [&](const T& x) { return x / (root + root); })};
  }
  friend Dual atan2(const Dual& y, const Dual& x) {
    using std::atan2;
    const T& v = y.value_;
    const T& u = x.value_;
    const T r2 = u * u + v * v;
    return {atan2(v, u), combine(y, x, [&](const T& dy, const T& dx) { return (u * dy - v * dx) / r2; })};
  }

  // The branch-free operations of scalar_ops.hpp: the branch the values choose, with its tangent.
  friend Dual select_greater(const Dual& a, const Dual& b, const Dual& x, const Dual& y) {
    const auto pick = [&](const T& u, const T& v) { return select_greater(a.value_, b.value_, u, v); };
    return {pick(x.value_, y.value_), combine(x, y, pick)};
  }
  // (C4)'s choice of path: as select_greater, the tangents of the path taken (only that path
  // need be computed: the generated code's if/else, emit::Plan::guard).
  friend Dual select_path(const Dual& a, const Dual& b, const Dual& x, const Dual& y) {
    const auto pick = [&](const T& u, const T& v) { return select_path(a.value_, b.value_, u, v); };
    return {pick(x.value_, y.value_), combine(x, y, pick)};
  }
  // (D4): the refinement (R1) corrects the value; the tangent is the first pass's, which the
  // refined one equals to rounding (r = 0 in exact arithmetic for every input, so ∂r = 0).
  friend Dual refined_value(const Dual& refined, const Dual& first_pass) { return {refined.value_, first_pass.tangent_}; }
  friend Dual minimum(const Dual& a, const Dual& b) { return select_greater(a, b, b, a); }
  friend Dual maximum(const Dual& a, const Dual& b) { return select_greater(a, b, a, b); }
  friend Dual abs_value(const Dual& a) { return select_greater(a, Dual(T(0)), a, -a); }
  friend Dual equilibration_scale(const Dual& a) { return Dual(equilibration_scale(a.value_)); }

  // Comparisons of the values (status checks, is_finite_value).
  friend bool operator==(const Dual& a, const Dual& b) { return a.value_ == b.value_; }
  friend bool operator!=(const Dual& a, const Dual& b) { return !(a == b); }
  friend bool operator<(const Dual& a, const Dual& b) { return a.value_ < b.value_; }
  friend bool operator>(const Dual& a, const Dual& b) { return b < a; }
  friend bool operator<=(const Dual& a, const Dual& b) { return !(b < a); }
  friend bool operator>=(const Dual& a, const Dual& b) { return !(a < b); }

 private:
  // f(ẋ_j, ẏ_j) per direction; a constant's missing entries read as 0.
  template <class F>
  static Tangent combine(const Dual& a, const Dual& b, F&& f) {
    if (a.tangent_.empty() && b.tangent_.empty()) return {};
    const std::size_t m = std::max(a.tangent_.size(), b.tangent_.size());
    Tangent t;
    t.reserve(m);
    for (std::size_t j = 0; j < m; ++j) t.push_back(f(a.derivative(j), b.derivative(j)));
    return t;
  }
  template <class F>
  static Tangent map(const Dual& a, F&& f) {
    Tangent t;
    t.reserve(a.tangent_.size());
    for (const T& x : a.tangent_) t.push_back(f(x));
    return t;
  }

  T value_;
  Tangent tangent_;
};

}  // namespace sweepgen::solver

namespace std {
// What the reference solver reads of its scalar's limits: the arithmetic is T's.
template <class T>
class numeric_limits<sweepgen::solver::Dual<T>> : public numeric_limits<T> {
  using Dual = sweepgen::solver::Dual<T>;

 public:
  static Dual epsilon() { return Dual(numeric_limits<T>::epsilon()); }
  static Dual min() { return Dual(numeric_limits<T>::min()); }
  static Dual max() { return Dual(numeric_limits<T>::max()); }
  static Dual lowest() { return Dual(numeric_limits<T>::lowest()); }
  static Dual infinity() { return Dual(numeric_limits<T>::infinity()); }
  static Dual quiet_NaN() { return Dual(numeric_limits<T>::quiet_NaN()); }
};
}  // namespace std

namespace Eigen {
template <class T>
struct NumTraits<sweepgen::solver::Dual<T>> : GenericNumTraits<sweepgen::solver::Dual<T>> {
  using Real = sweepgen::solver::Dual<T>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 3,
    MulCost = 3,
  };
  static Real epsilon() { return Real(NumTraits<T>::epsilon()); }
  static Real dummy_precision() { return Real(NumTraits<T>::dummy_precision()); }
  static int digits10() { return NumTraits<T>::digits10(); }
};
}  // namespace Eigen
