// What each stored array of the sweeps is, as printed beside it in generated code: the sweep
// that computes it, the quantity in the notation of docs/derivation.md (ASCII), and the tags of
// the equations there that define it. The equations themselves are written only in
// docs/derivation.md. Every array the sweeps expose must have an entry; a missing one is a
// generator bug (std::logic_error), caught by the tests.
#pragma once

#include <string>

namespace sweepgen::emit {

struct Equation {
  const char* sweep;     // which sweep computes it
  const char* quantity;  // what it holds
  const char* tags;      // docs/derivation.md tags, e.g. "I1" or "S2, C1, C2"

  // "<quantity> (<tags>)", the text generated code prints.
  std::string cited() const { return std::string(quantity) + " (" + tags + ")"; }
};

// For "articulated_force_<track>" and "acceleration_energy_<track>" pass the array name;
// the track suffix is ignored.
const Equation& equation_of(const std::string& array);

}  // namespace sweepgen::emit
