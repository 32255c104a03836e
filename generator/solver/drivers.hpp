// The motion drivers of a problem (paper §3) and how the inward sweep keeps them apart.
//
// A *track* is one articulated force F^A and acceleration-energy E^A recursion. Alg. 1 (the
// composed sweep) has a single track holding the velocity-product bias and every driver;
// Alg. 2 (the decomposition sweeps) has one track for the bias and one per driver instance.
// Any grouping in between is allowed; by linearity the composed result is the sum of the
// tracks (docs/derivation.md, "Linearity").
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "model/chain.hpp"

namespace sweepgen::solver {

constexpr std::size_t kMaxConstraints = 6;

struct ExternalForceDriver {
  std::string name;
  std::string link;  // URDF link the wrench acts on (given in its frame, about its origin)
};

struct Track {
  std::string name;
  bool bias = false;                  // carries the velocity-product terms Fb, Ẍb
  std::vector<std::size_t> torques;   // indices into DriverLayout::torques
  std::vector<std::size_t> external_forces;  // indices into DriverLayout::external_forces

  // Pure external-force tracks are what Alg. 4 keeps out of the constraint's reaction.
  bool only_external_forces() const { return !bias && torques.empty() && !external_forces.empty(); }
};

struct DriverLayout {
  std::vector<std::string> torques;                    // feed-forward torque instances
  std::vector<ExternalForceDriver> external_forces;    // external-force instances
  std::size_t constraints = 0;                         // Nc, 0..6
  std::vector<Track> tracks;

  // One track with everything (Alg. 1).
  void compose_all();
  // The bias and every instance on a track of its own (Alg. 2).
  void decompose_all();
  // Alg. 4 needs every external force on a pure external-force track.
  bool external_forces_separable() const;
};

// Throws InputError (naming `source`) if a name is unknown, a link is fixed to the base,
// Nc is out of range, or a driver instance sits on no track or on two.
void validate(const DriverLayout& layout, const model::Chain& chain, const std::string& source);

}  // namespace sweepgen::solver
