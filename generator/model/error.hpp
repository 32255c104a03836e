// Errors in user input: every message names the file, the element and the reason.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace sweepgen {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& element, const std::string& reason)
      : std::runtime_error(file + ": " + element + ": " + reason) {}
};

// " (did you mean 'x'?)" for the candidate closest to `name` by edit distance, or "".
std::string nearest_name_hint(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace sweepgen
