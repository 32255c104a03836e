#include "emit/literal.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace sweepgen::emit {

std::string literal(double value, const std::string& scalar) {
  if (std::isnan(value)) throw std::logic_error("literal: NaN constant in generated code");
  if (std::isinf(value))
    return std::string(value < 0 ? "-" : "") + (scalar == "float" ? "HUGE_VALF" : "HUGE_VAL");  // <cmath>; host and device
  char buffer[64];
  const bool single = scalar == "float";
  const auto result = single ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value))
                             : std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".e") == std::string::npos) text += ".0";  // "2" would be an int
  return single ? text + "f" : text;
}

}  // namespace sweepgen::emit
