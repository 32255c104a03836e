// The runtime every generated source carries verbatim (templates/lanes.mustache), compiled here
// once per test executable, and the error measure its functions' tests judge them by: ulps of a
// result against the exact value in binary128 (libquadmath).
#pragma once

#include <quadmath.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace sweepgen::generated_lanes {
#include "../../templates/lanes.mustache"
}  // namespace sweepgen::generated_lanes

namespace sweepgen::test {

// |got - exact| in units of the last place of the exact value rounded to T (the gap above it).
template <class T>
double ulps(T got, __float128 exact) {
  const T rounded = static_cast<T>(exact);
  const T gap = std::nextafter(std::fabs(rounded), std::numeric_limits<T>::infinity()) - std::fabs(rounded);
  return static_cast<double>(fabsq(static_cast<__float128>(got) - exact) / gap);
}

}  // namespace sweepgen::test
