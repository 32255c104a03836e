#include "model/input_limits.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "model/error.hpp"

namespace sweepgen {

std::string magnitude_problem(double value) {
  const double magnitude = std::abs(value);
  if (magnitude == 0 || (magnitude >= kSmallestModelNumber && magnitude <= kLargestModelNumber)) return "";
  std::ostringstream text;
  text.precision(17);
  text << value << " is outside the range of a robot's numbers: 0, or 1e-60 to 1e60 in magnitude (README, \"Limits\")";
  return text.str();
}

std::string size_text(std::size_t bytes) {
  if (bytes % (std::size_t{1} << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

std::string read_input_file(const std::string& path, std::size_t limit, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "file", "cannot be opened for reading");
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > limit)
      throw InputError(path, "file",
                       "larger than " + size_text(limit) + ", the limit for a " + what + " (README, \"Limits\"); not read further");
  }
  if (in.bad()) throw InputError(path, "file", "cannot be read");
  return text;
}

}  // namespace sweepgen
