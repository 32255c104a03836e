// The atan2 of generated code (templates/lanes.mustache, atan2_lanes and atan2_of: the rotation
// angle of a closure error (L3), in a flat call and in a batch's lanes), against binary128
// (libquadmath): within 1 ulp at random points of every octant over magnitudes from 2^-1000 to
// 2^1000, next to the octants' edges (|y| = |x|, |y| = tan(pi/8) |x|, the axes), for ratios from
// the subnormals up and at the largest doubles; the C library's for two zeros, Inf and NaN; the
// same bits in a scalar call and a batch's lanes; float through double, rounded once. And the
// square root of a batch's lanes (sqrt_lanes, the lanes' ISA's instruction): the C library's bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

#include "support/lanes_runtime.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using namespace generated_lanes;
using test::ulps;

// The requirement on generated code's atan2 (it replaces the C library's in the closure errors):
// at most 1 ulp from the exact value: the last rounding's half, P's 0.05 from atan and the
// tail's roundings, each a few units of 2^-53 of at most 0.2 of the angle (lanes.mustache, where u
// is carried in two parts: with u rounded once the error reached 1.85 ulp). Measured: 0.67 ulp.
constexpr double kMaxUlps = 1.0;

struct Worst {
  double ulps = 0, y = 0, x = 0;
  void add(double y_value, double x_value, double got) {
    const double e = test::ulps(got, atan2q(y_value, x_value));
    if (e > ulps) ulps = e, y = y_value, x = x_value;
  }
};

// Points (y, x) of every octant and sign: |y| / |x| next to 0, tan(pi/8), 1, 1/tan(pi/8) and far
// beyond, at magnitudes from 2^-1000 to 2^1000.
std::vector<std::pair<double, double>> points(int count) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0, 1), exponent(-1000, 1000), log_ratio(-60, 60);
  std::vector<std::pair<double, double>> p;
  const double edges[] = {0.41421356237309503, 1.0, 2.414213562373095};
  for (int i = 0; i < count; ++i) {
    const double x = std::ldexp(1 + unit(rng), static_cast<int>(exponent(rng)) / (i % 3 ? 500 : 1));
    double ratio;
    switch (i % 4) {
      case 0: ratio = unit(rng) * 3; break;                                   // the octants near the x axis
      case 1: ratio = std::exp2(log_ratio(rng)); break;                      // far from it both ways
      case 2: ratio = edges[i % 3] * (1 + (unit(rng) - 0.5) * 1e-12); break;  // next to an edge
      default: ratio = edges[i % 3]; for (int j = i % 7; j > 0; --j) ratio = std::nextafter(ratio, 0.0); break;
    }
    const double y = x * ratio;
    p.emplace_back(i & 8 ? -y : y, i & 16 ? -x : x);
    p.emplace_back(i & 8 ? -x : x, i & 16 ? -y : y);  // the same ratio from the other axis
  }
  // The ratio y / x from the smallest subnormal up, either sign, both sides of the y axis.
  for (double v = std::numeric_limits<double>::denorm_min(); v < 1; v *= 1.9)
    for (double x : {1.0, -1.0}) p.emplace_back(v, x), p.emplace_back(-v, x), p.emplace_back(x, v), p.emplace_back(x, -v);
  return p;
}

TEST(Atan2Lanes, WithinOneUlpInEveryOctant) {
  const auto p = points(test::state_count(200000));
  Worst worst;
  for (const auto& [y, x] : p) worst.add(y, x, atan2_lanes(y, x));
  std::cout << p.size() << " points: worst " << worst.ulps << " ulp (y = " << worst.y << ", x = " << worst.x << ")\n";
  EXPECT_LE(worst.ulps, kMaxUlps) << "at y = " << worst.y << ", x = " << worst.x;
}

TEST(Atan2Lanes, TheCLibrarysForTwoZerosInfAndNaN) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double big = 0x1p1001, huge = std::numeric_limits<double>::max();
  const double values[] = {0.0, -0.0, inf, -inf, nan, big, -huge, 1.5, -2.0};
  int compared = 0, in_range = 0;
  for (double y : values)
    for (double x : values) {
      const double got = atan2_lanes(y, x);
      if (std::isfinite(x) && std::isfinite(y) && (x != 0 || y != 0)) {
        EXPECT_LE(ulps(got, atan2q(y, x)), kMaxUlps) << "atan2(" << y << ", " << x << ")";  // the polynomial's
        ++in_range;
        continue;
      }
      const double expected = std::atan2(y, x);
      EXPECT_TRUE(std::isnan(expected) ? std::isnan(got) : std::memcmp(&got, &expected, sizeof got) == 0)
          << "atan2(" << y << ", " << x << ") = " << got << ", the C library's " << expected;
      ++compared;
    }
  EXPECT_EQ(in_range, 6 * 6 - 4);  // the six finite values paired, but not two zeros
  EXPECT_EQ(compared, 9 * 9 - in_range);
  // A signed zero's angle keeps the sign (y = -0: -0 from the +x side, -pi from the -x side).
  EXPECT_TRUE(std::signbit(atan2_lanes(-0.0, 3.0)) && atan2_lanes(-0.0, 3.0) == 0);
  EXPECT_EQ(atan2_lanes(-0.0, -3.0), -static_cast<double>(acosq(-1)));
}

#if defined(SWEEPGEN_BATCH_BYTES)
TEST(Atan2Lanes, AScalarCallAndABatchsLanesAgreeBitForBit) {
  const auto p = points(test::state_count(20000));
  constexpr int width = Lanes<BatchF64>::width;
  const double inf = std::numeric_limits<double>::infinity();
  for (std::size_t first = 0; first + width <= p.size(); first += width) {
    BatchF64 y, x;
    for (int l = 0; l < width; ++l) y[l] = p[first + l].first, x[l] = p[first + l].second;
    if (first % (8 * width) == 0) y[first / (8 * width) % width] = (first / width) % 3 ? inf : 0.0;  // a lane beyond
    const BatchF64 angle = atan2_lanes(y, x);
    for (int l = 0; l < width; ++l) {
      const double scalar = atan2_of(y[l], x[l]), lane = angle[l];  // a vector element has no address in clang
      ASSERT_EQ(std::memcmp(&lane, &scalar, sizeof scalar), 0) << "y = " << y[l] << ", x = " << x[l];
    }
  }
}
#endif

TEST(Atan2Lanes, FloatIsTheDoubleRoundedOnce) {
  // A float result is the double one (within kMaxUlps of a double's ulp, 2^-29 of a float's)
  // rounded to float: within half a float ulp and that.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  double worst = 0;
  for (int trial = 0; trial < test::state_count(40000); ++trial) {
    const float y = coordinate(rng), x = coordinate(rng);
    worst = std::max(worst, ulps(atan2_of(y, x), atan2q(y, x)));
#if defined(SWEEPGEN_BATCH_BYTES)
    BatchF32 ys{}, xs{};
    ys[trial % Lanes<BatchF32>::width] = y, xs[trial % Lanes<BatchF32>::width] = x;
    const float lane = atan2_of(ys, xs)[trial % Lanes<BatchF32>::width], scalar = atan2_of(y, x);
    ASSERT_EQ(std::memcmp(&lane, &scalar, sizeof lane), 0) << y << ", " << x;
#endif
  }
  std::cout << "float: worst " << worst << " ulp\n";
  EXPECT_LE(worst, 0.5 + kMaxUlps * std::ldexp(1.0, -29));
}

#if defined(SWEEPGEN_BATCH_BYTES)
// Every lane of sqrt_of(Batch) holds the bits of the C library's root of that lane (what a flat
// call computes): zeros of both signs, subnormals, random magnitudes over the whole range, the
// largest values, Inf, and the NaN of a negative value, of -Inf and of a NaN.
template <class T, class B>
void expect_lanes_as_the_c_library(std::mt19937_64& rng) {
  constexpr int width = Lanes<B>::width;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  std::vector<T> values{T(0), -T(0), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(),
                        std::numeric_limits<T>::max(), T(1), T(2), T(4), inf, -inf, nan, -nan, T(-1),
                        -std::numeric_limits<T>::denorm_min()};
  std::uniform_real_distribution<T> mantissa(T(1), T(2));
  std::uniform_int_distribution<int> exponent(std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits,
                                              std::numeric_limits<T>::max_exponent - 1);
  for (int draw = 0; draw < test::state_count(20000); ++draw) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  for (std::size_t first = 0; first < values.size(); first += width) {
    B x{};
    for (int l = 0; l < width; ++l) x[l] = values[(first + l) % values.size()];
    const B root = sqrt_of(x);
    for (int l = 0; l < width; ++l) {
      const T lane = root[l], scalar = std::sqrt(x[l]);
      ASSERT_EQ(std::memcmp(&lane, &scalar, sizeof lane), 0) << "x = " << x[l] << ": " << lane << " against " << scalar;
    }
  }
}

TEST(SqrtLanes, EveryLaneTheCLibrarysBits) {
  std::mt19937_64 rng(11);
  expect_lanes_as_the_c_library<double, BatchF64>(rng);
  expect_lanes_as_the_c_library<float, BatchF32>(rng);
}
#endif

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
