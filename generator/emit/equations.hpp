// The equation each stored array implements, as printed beside it in generated code (in the
// notation of docs/achd-equations.md, ASCII). Every array the sweeps expose must have one;
// a missing entry is a generator bug (std::logic_error), caught by the tests.
#pragma once

#include <string>

namespace sweepgen::emit {

struct Equation {
  const char* sweep;     // which sweep computes it
  const char* formula;
};

// For "articulated_force_<track>" and "acceleration_energy_<track>" pass the array name;
// the track suffix is ignored.
const Equation& equation_of(const std::string& array);

}  // namespace sweepgen::emit
