// Errors in user input: every message names the file, the element and the reason.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "model/inert_text.hpp"

namespace sweepgen {

// what() is a C string: a NUL byte in a name taken from the input (YAML "\0", JSON "\u0000") would
// cut the message there, dropping the element or the reason. Messages spell NUL as "\0".
inline std::string message_text(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\0') out += "\\0";
    else out += c;
  }
  return out;
}

// The element path `parent.key` of a scene entry named by the input (a joint name under
// rotor_inertia, an unknown key): `key` as it is when it is a plain name (letters, digits, '_',
// '-'), quoted otherwise.
std::string element_path(const std::string& parent, const std::string& key);

// `file`: the input's path, alone or with ":line:column" (or "command line", an option): shown
// through inert_text, so that a path holding a line break or a quote cannot split or blur the
// message. `element` and `reason` quote what they take from the input themselves (quote_name).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& element, const std::string& reason)
      : std::runtime_error(message_text(inert_text(file, kShownPathBytes) + ": " + element + ": " + reason)), file_(file) {}
  // The file part as given, unescaped.
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

// " (did you mean 'x'?)" for the candidate closest to `name` by edit distance, or "".
std::string nearest_name_hint(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace sweepgen
