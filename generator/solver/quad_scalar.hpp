// IEEE binary128 ("quad", 113-bit mantissa, eps = 2^-112 ≈ 1.9e-34) as a scalar for the
// templated reference solver and for Eigen: the high-precision referee of the numerical-
// stability suite (docs/stability.md). long double (64-bit mantissa on x86-64, eps ≈ 1.1e-19)
// cannot judge double where double loses more than ~3 of its 16 digits; quad can judge it
// down to a relative error of ~1e-30.
//
// Quad wraps GCC's __float128 (arithmetic in libgcc, sqrt/sin/cos/printing in libquadmath:
// link `quadmath`). A class rather than the raw type because under strict ISO C++ (the
// project builds with -std=c++17, no GNU extensions) std::numeric_limits and
// std::is_floating_point know nothing of __float128 and std::cos(__float128) is ambiguous;
// a class gets its functions by argument-dependent lookup (the solver calls sin, cos, sqrt
// and scalar_ops.hpp's selects unqualified), and specialising std::numeric_limits and
// Eigen::NumTraits for it is legal.
//
// Only GCC-compatible compilers on targets with __float128 (x86-64, ...) have it.
#pragma once

#include <quadmath.h>

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <ostream>
#include <type_traits>

namespace sweepgen::solver {

__extension__ typedef __float128 float128;

class Quad {
 public:
  constexpr Quad() : v_(0) {}
  // From any built-in arithmetic type (exact for float, double, long double and integers
  // below 2^113), implicitly, so that Quad mixes with literals as double does.
  template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  constexpr Quad(T x) : v_(static_cast<float128>(x)) {}
  static constexpr Quad from_raw(float128 x) {
    Quad q;
    q.v_ = x;
    return q;
  }
  constexpr float128 raw() const { return v_; }
  // To a built-in type, rounding to nearest; explicit, so that no precision is lost unnoticed.
  template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  explicit constexpr operator T() const {
    return static_cast<T>(v_);
  }

  constexpr Quad operator-() const { return from_raw(-v_); }
  constexpr Quad operator+() const { return *this; }
  Quad& operator+=(const Quad& o) { v_ += o.v_; return *this; }
  Quad& operator-=(const Quad& o) { v_ -= o.v_; return *this; }
  Quad& operator*=(const Quad& o) { v_ *= o.v_; return *this; }
  Quad& operator/=(const Quad& o) { v_ /= o.v_; return *this; }

  friend constexpr Quad operator+(const Quad& a, const Quad& b) { return from_raw(a.v_ + b.v_); }
  friend constexpr Quad operator-(const Quad& a, const Quad& b) { return from_raw(a.v_ - b.v_); }
  friend constexpr Quad operator*(const Quad& a, const Quad& b) { return from_raw(a.v_ * b.v_); }
  friend constexpr Quad operator/(const Quad& a, const Quad& b) { return from_raw(a.v_ / b.v_); }
  friend constexpr bool operator==(const Quad& a, const Quad& b) { return a.v_ == b.v_; }
  friend constexpr bool operator!=(const Quad& a, const Quad& b) { return a.v_ != b.v_; }
  friend constexpr bool operator<(const Quad& a, const Quad& b) { return a.v_ < b.v_; }
  friend constexpr bool operator<=(const Quad& a, const Quad& b) { return a.v_ <= b.v_; }
  friend constexpr bool operator>(const Quad& a, const Quad& b) { return a.v_ > b.v_; }
  friend constexpr bool operator>=(const Quad& a, const Quad& b) { return a.v_ >= b.v_; }

 private:
  float128 v_;
};

// The functions the solver, the tests and Eigen's decompositions call, found by ADL.
inline Quad sqrt(const Quad& x) { return Quad::from_raw(sqrtq(x.raw())); }
inline Quad sin(const Quad& x) { return Quad::from_raw(sinq(x.raw())); }
inline Quad cos(const Quad& x) { return Quad::from_raw(cosq(x.raw())); }
inline Quad abs(const Quad& x) { return Quad::from_raw(fabsq(x.raw())); }
inline Quad fabs(const Quad& x) { return abs(x); }
inline Quad exp(const Quad& x) { return Quad::from_raw(expq(x.raw())); }
inline Quad log(const Quad& x) { return Quad::from_raw(logq(x.raw())); }
inline Quad pow(const Quad& x, const Quad& y) { return Quad::from_raw(powq(x.raw(), y.raw())); }
inline Quad atan2(const Quad& y, const Quad& x) { return Quad::from_raw(atan2q(y.raw(), x.raw())); }
inline Quad floor(const Quad& x) { return Quad::from_raw(floorq(x.raw())); }
inline Quad ceil(const Quad& x) { return Quad::from_raw(ceilq(x.raw())); }
inline bool isnan(const Quad& x) { return isnanq(x.raw()) != 0; }
inline bool isinf(const Quad& x) { return isinfq(x.raw()) != 0; }
inline bool isfinite(const Quad& x) { return !isnan(x) && !isinf(x); }

// scalar_ops.hpp's branch-free operations (its templates take built-in floating types only).
inline Quad select_greater(const Quad& a, const Quad& b, const Quad& if_greater, const Quad& otherwise) {
  return a > b ? if_greater : otherwise;
}
inline Quad select_path(const Quad& a, const Quad& b, const Quad& if_greater, const Quad& otherwise) {
  return a > b ? if_greater : otherwise;
}
inline Quad minimum(const Quad& a, const Quad& b) { return b < a ? b : a; }
inline Quad maximum(const Quad& a, const Quad& b) { return a < b ? b : a; }
inline Quad abs_value(const Quad& a) { return abs(a); }
inline Quad refined_value(const Quad& refined, const Quad& /*first_pass*/) { return refined; }
inline Quad equilibration_scale(const Quad& x) {  // as scalar_ops.hpp's
  const int k = x > Quad(0) ? ilogbq(x.raw()) : 0;
  return x > Quad(0) ? Quad::from_raw(ldexpq(1, ((k & 1) - k) / 2)) : Quad(0);
}

// 36 significant digits (enough to round-trip binary128).
inline std::ostream& operator<<(std::ostream& out, const Quad& x) {
  char text[64];
  quadmath_snprintf(text, sizeof text, "%.36Qg", x.raw());
  return out << text;
}

}  // namespace sweepgen::solver

namespace std {
template <>
class numeric_limits<sweepgen::solver::Quad> {
  using Quad = sweepgen::solver::Quad;

 public:
  static constexpr bool is_specialized = true;
  static constexpr bool is_signed = true;
  static constexpr bool is_integer = false;
  static constexpr bool is_exact = false;
  static constexpr bool has_infinity = true;
  static constexpr bool has_quiet_NaN = true;
  static constexpr bool has_signaling_NaN = true;
  static constexpr bool is_iec559 = true;
  static constexpr bool is_bounded = true;
  static constexpr bool is_modulo = false;
  static constexpr int radix = 2;
  static constexpr int digits = FLT128_MANT_DIG;  // 113
  static constexpr int digits10 = FLT128_DIG;     // 33
  static constexpr int max_digits10 = 36;
  static constexpr int min_exponent = FLT128_MIN_EXP;
  static constexpr int max_exponent = FLT128_MAX_EXP;
  static constexpr int min_exponent10 = FLT128_MIN_10_EXP;
  static constexpr int max_exponent10 = FLT128_MAX_10_EXP;
  static constexpr float_round_style round_style = round_to_nearest;
  static Quad epsilon() { return Quad::from_raw(ldexpq(1, 1 - FLT128_MANT_DIG)); }  // 2^-112
  static Quad min() { return Quad::from_raw(ldexpq(1, FLT128_MIN_EXP - 1)); }  // 2^-16382
  static Quad max() { return Quad::from_raw(ldexpq(2 - ldexpq(1, 1 - FLT128_MANT_DIG), FLT128_MAX_EXP - 1)); }
  static Quad lowest() { return -max(); }
  static Quad denorm_min() { return Quad::from_raw(ldexpq(1, FLT128_MIN_EXP - FLT128_MANT_DIG)); }
  static Quad round_error() { return Quad(0.5); }
  static Quad infinity() { return Quad::from_raw(static_cast<__float128>(std::numeric_limits<double>::infinity())); }
  static Quad quiet_NaN() { return Quad::from_raw(nanq("")); }
  static Quad signaling_NaN() { return quiet_NaN(); }
};
}  // namespace std

namespace Eigen {
template <>
struct NumTraits<sweepgen::solver::Quad> : GenericNumTraits<sweepgen::solver::Quad> {
  using Quad = sweepgen::solver::Quad;
  using Real = Quad;
  using NonInteger = Quad;
  using Nested = Quad;
  using Literal = Quad;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2,
    AddCost = 20,  // software arithmetic
    MulCost = 30,
  };
  // What Eigen's iterative decompositions (eigenvalues, SVD) take as "converged".
  static Quad dummy_precision() { return Quad(1e-30); }
  static int digits10() { return FLT128_DIG; }
};
}  // namespace Eigen

// The referee, ReferenceSolver<Quad>, is compiled once, in reference_solver_quad.cpp of
// sweepgen_measure (which links quadmath): a translation unit that includes this header does not
// instantiate the sweeps in binary128 again (3-4 s of compile each).
#include "solver/reference_solver.hpp"

namespace sweepgen::solver {
extern template class ReferenceSolver<Quad>;
}  // namespace sweepgen::solver
