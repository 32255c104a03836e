// Numbers printed so that they read back to the same value (style.md, item 8).
#pragma once

#include <string>

namespace sweepgen::emit {

// A C++ literal of type `scalar` ("double" or "float") for `value`: the shortest decimal that
// round-trips in that type (std::to_chars), always with a '.' or exponent, 'f'-suffixed for
// float; infinities as HUGE_VAL / HUGE_VALF of <cmath> (constants on the host and on a GPU).
std::string literal(double value, const std::string& scalar);

}  // namespace sweepgen::emit
