// The few data-dependent operations the sweeps need, written branch-free so that a symbolic
// scalar can trace them (it overloads these names; calls are unqualified so ADL finds them).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace sweepgen::solver {

// a > b ? if_greater : otherwise
template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar select_greater(const Scalar& a, const Scalar& b, const Scalar& if_greater, const Scalar& otherwise) {
  return a > b ? if_greater : otherwise;
}

// a > b ? if_greater : otherwise, where a caller computed both operands only to choose one: the
// generated code computes only the chosen path's (symbolic Op::select_path, emit::Plan::guard).
// In arithmetic, the same as select_greater.
template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar select_path(const Scalar& a, const Scalar& b, const Scalar& if_greater, const Scalar& otherwise) {
  return a > b ? if_greater : otherwise;
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar minimum(const Scalar& a, const Scalar& b) {
  return std::min(a, b);
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar maximum(const Scalar& a, const Scalar& b) {
  return std::max(a, b);
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar abs_value(const Scalar& a) {
  return std::abs(a);
}

// The refined pass's value, differentiated as the first pass (docs/derivation.md, D4): the dual
// scalar (dual_scalar.hpp) takes `first_pass`'s tangent; in arithmetic it is `refined` itself.
template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar refined_value(const Scalar& refined, const Scalar& /*first_pass*/) {
  return refined;
}

// The layout of an IEEE float or double, for equilibration_scale.
template <class T>
struct FloatFormat {
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
  static constexpr int mantissa_bits = sizeof(T) == 8 ? 52 : 23;
  static constexpr int bias = sizeof(T) == 8 ? 1023 : 127;
  static constexpr T min_normal = sizeof(T) == 8 ? T(0x1p-1022) : T(0x1p-126f);
  static constexpr T max_finite = sizeof(T) == 8 ? T(0x1.fffffffffffffp+1023) : T(0x1.fffffep+127f);
};

// The power of two s with s² x in [1, 4) for x > 0 (x = f 2^k, f in [1, 2): s = 2^-floor(k/2)),
// and 0 for x <= 0 or NaN. Multiplying by it is exact (no rounding), so it rescales a quantity
// to unit order without changing any digit: the constraint factorisation equilibrates
// E^A_cstr,0 with it (constraint_multipliers.hpp). Generated code spells it the same way
// (templates/lanes.mustache, the same lines, and there its lanes' form). For IEEE float and
// double it reads and writes the exponent field, branch-free (no libm call: ilogb and ldexp cost
// ~60 instructions each, six times a solve at Nc = 6); other scalars go through ilogb and ldexp.
template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar equilibration_scale(const Scalar& x) {
  if constexpr (std::numeric_limits<Scalar>::is_iec559 && (sizeof(Scalar) == 4 || sizeof(Scalar) == 8)) {
    using T = Scalar;
    using F = FloatFormat<T>;
    using Bits = typename F::Bits;
    // A subnormal x is first scaled by 2^mantissa_bits (exactly) into the normal range.
    const bool subnormal = x < F::min_normal;
    const T normal = subnormal ? x * T(Bits(1) << F::mantissa_bits) : x;
    Bits bits;
    std::memcpy(&bits, &normal, sizeof bits);
    const int k = static_cast<int>((bits >> F::mantissa_bits) & Bits(2 * F::bias + 1)) - F::bias - (subnormal ? F::mantissa_bits : 0);
    const Bits scale_bits = static_cast<Bits>(((k & 1) - k) / 2 + F::bias) << F::mantissa_bits;
    T scale;
    std::memcpy(&scale, &scale_bits, sizeof scale);
    // 0 for x <= 0, NaN and +Inf.
    return ((x > T(0)) & (x <= F::max_finite)) ? scale : T(0);
  } else {
    const int k = x > Scalar(0) ? std::ilogb(x) : 0;
    return x > Scalar(0) ? std::ldexp(Scalar(1), ((k & 1) - k) / 2) : Scalar(0);
  }
}

// Neither NaN nor ±Inf, for any IEEE-style scalar (x − x is NaN exactly for those).
template <class Scalar>
bool is_finite_value(const Scalar& x) {
  return x - x == Scalar(0);
}

template <class Derived>
bool all_finite(const Eigen::DenseBase<Derived>& values) {
  for (Eigen::Index i = 0; i < values.size(); ++i)
    if (!is_finite_value(values.derived().coeff(i))) return false;
  return true;
}

// x clamped to [-limit, limit].
template <class Scalar>
Scalar clamp_symmetric(const Scalar& x, const Scalar& limit) {
  return minimum(maximum(x, Scalar(-limit)), limit);
}

}  // namespace sweepgen::solver
