// The synthetic robot family of the numerical-stability suite (robots/family/README.md,
// docs/stability.md): robots that stress the solver's arithmetic, each written as a URDF and a
// scene by `sweepgen family`. Deterministic: every random number comes from a seeded
// mt19937_64 (fully specified by the C++ standard) through our own uniform mapping, and the
// only math function used is sqrt (correctly rounded), so the files are identical on every
// IEEE-754 platform.
#pragma once

#include <string>
#include <vector>

#include "family/robot_spec.hpp"

namespace sweepgen::family {

struct FamilyCase {
  std::string name;
  std::string purpose;           // one line: what the case stresses
  RobotSpec robot;
  std::string tip;               // tip link = the last moving link (no fixed joints: KDL can take it)
  std::string force_link;        // a mid-chain link for the second external-force instance
  double length_scale = 1;       // typical link length [m]
  double mass_scale = 1;         // typical link mass [kg]
  bool heavy = false;            // long chains: reduced in CI (docs/stability.md)
  // A configuration where the tip's 6 constraint directions are singular (stretched arm,
  // aligned wrist axes); empty when the case has none by construction.
  std::vector<double> singular_q;
};

// Every case, in a fixed order.
const std::vector<std::string>& family_case_names();
// Throws InputError for an unknown name (with a nearest-name hint).
FamilyCase family_case(const std::string& name);

// The scene: torque instance tau_ff, external forces f_tip (tip) and f_mid (force_link),
// Nc = 6 run-time directions, decomposed, policy original, scalars double and float.
std::string scene_text(const FamilyCase& c);

}  // namespace sweepgen::family
