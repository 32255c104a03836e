// The sin and cos of generated code (templates/lanes.mustache, sincos_lanes and sincos_each: the
// joint angles of a scalar solve in vector lanes, a batch's lanes, a GPU thread's angles), against
// binary128 (libquadmath): within 1 ulp over the joint range [-1e4, 1e4] rad, at random points,
// next to every multiple of pi/2 there (where x - k pi/2 cancels) and from the subnormals up; the
// C library's beyond the range and for Inf and NaN; the same bits in a scalar's packed lanes and a
// batch's; float through double, rounded once.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <random>

#include "support/lanes_runtime.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using namespace generated_lanes;
using test::ulps;

// The worst error over values x, the angles taken seven at a time (a 7-joint arm's sincos_each).
struct Worst {
  double sin = 0, cos = 0;
  double sin_at = 0, cos_at = 0;
  void add(const std::vector<double>& x) {
    for (std::size_t first = 0; first + 7 <= x.size(); first += 7) {
      double angle[7], sines[7], cosines[7];
      std::copy_n(x.begin() + static_cast<std::ptrdiff_t>(first), 7, angle);
      sincos_each(angle, sines, cosines);
      for (int i = 0; i < 7; ++i) {
        const double s = ulps(sines[i], sinq(angle[i])), c = ulps(cosines[i], cosq(angle[i]));
        if (s > sin) sin = s, sin_at = angle[i];
        if (c > cos) cos = c, cos_at = angle[i];
      }
    }
  }
};

// The requirement on generated code's sin and cos (they replace the C library's on the joint
// range): at most 1 ulp from the exact value. Measured: 0.78 ulp.
constexpr double kMaxUlps = 1.0;
constexpr double kRange = 1e4;  // sincos_lanes' range

TEST(SincosLanes, WithinOneUlpOverTheJointRange) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> joint(-2 * M_PI, 2 * M_PI), wide(-kRange, kRange);
  std::vector<double> x;
  for (int i = 0; i < test::state_count(140000); ++i) x.push_back(i % 2 ? joint(rng) : wide(rng));
  // Next to each multiple of pi/2 in the range: the double nearest it and three on either side.
  const __float128 pi_2 = acosq(-1) / 2;
  for (int k = -6366; k <= 6366; ++k) {
    double near = static_cast<double>(k * pi_2);
    for (int j = 0; j < 3; ++j) near = std::nextafter(near, -kRange);
    for (int j = 0; j < 7; ++j, near = std::nextafter(near, kRange)) x.push_back(near);
  }
  // From the smallest subnormal to 1, both signs.
  for (double v = std::numeric_limits<double>::denorm_min(); v < 1; v *= 1.9) {
    x.push_back(v);
    x.push_back(-v);
  }
  for (double v : {0.0, -0.0, kRange, -kRange, M_PI, -M_PI / 2}) x.push_back(v);
  while (x.size() % 7) x.push_back(1.0);
  Worst worst;
  worst.add(x);
  std::cout << x.size() << " values: worst sin " << worst.sin << " ulp (x = " << worst.sin_at << "), worst cos "
            << worst.cos << " ulp (x = " << worst.cos_at << ")\n";
  EXPECT_LE(worst.sin, kMaxUlps) << "at x = " << worst.sin_at;
  EXPECT_LE(worst.cos, kMaxUlps) << "at x = " << worst.cos_at;
}

TEST(SincosLanes, TheCLibrarysBeyondTheRange) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  double angle[7] = {kRange * 1.0000001, -3e5, 1e300, inf, -inf, nan, 0.5};
  double sines[7], cosines[7];
  sincos_each(angle, sines, cosines);
  for (int i = 0; i < 5; ++i) {
    const double s = std::sin(angle[i]), c = std::cos(angle[i]);
    EXPECT_TRUE(std::isnan(s) ? std::isnan(sines[i]) : sines[i] == s) << angle[i];
    EXPECT_TRUE(std::isnan(c) ? std::isnan(cosines[i]) : cosines[i] == c) << angle[i];
  }
  EXPECT_TRUE(std::isnan(sines[5]) && std::isnan(cosines[5]));
  EXPECT_LE(ulps(sines[6], sinq(0.5)), kMaxUlps);  // a lane in range beside them keeps the polynomial
}

#if defined(SWEEPGEN_BATCH_BYTES)
TEST(SincosLanes, AScalarsPackedAnglesAndABatchsLanesAgreeBitForBit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> wide(-kRange, kRange);
  constexpr int width = Lanes<BatchF64>::width;
  for (int trial = 0; trial < 1000; ++trial) {
    double angle[5], sines[5], cosines[5];
    for (double& a : angle) a = wide(rng);
    sincos_each(angle, sines, cosines);
    BatchF64 lanes[5], lane_sines[5], lane_cosines[5];
    for (int i = 0; i < 5; ++i)
      for (int l = 0; l < width; ++l) lanes[i][l] = angle[(i + l) % 5];
    sincos_each(lanes, lane_sines, lane_cosines);
    for (int i = 0; i < 5; ++i)
      for (int l = 0; l < width; ++l) {
        ASSERT_EQ(lane_sines[i][l], sines[(i + l) % 5]) << angle[(i + l) % 5];
        ASSERT_EQ(lane_cosines[i][l], cosines[(i + l) % 5]) << angle[(i + l) % 5];
      }
  }
}
#endif

TEST(SincosLanes, FloatIsTheDoubleRoundedOnce) {
  // A float result is the double one (within kMaxUlps of a double's ulp, 2^-29 of a float's)
  // rounded to float: within half a float ulp and that.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> joint(-7.0f, 7.0f);
  double worst = 0;
  for (int trial = 0; trial < test::state_count(20000); ++trial) {
    float angle[3], sines[3], cosines[3];
    for (float& a : angle) a = joint(rng);
    sincos_each(angle, sines, cosines);
    for (int i = 0; i < 3; ++i) worst = std::max({worst, ulps(sines[i], sinq(angle[i])), ulps(cosines[i], cosq(angle[i]))});
  }
  std::cout << "float: worst " << worst << " ulp\n";
  EXPECT_LE(worst, 0.5 + kMaxUlps * std::ldexp(1.0, -29));
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen
