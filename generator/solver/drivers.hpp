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

// Directions one constraint set can hold (a rigid body has six), and all sets together.
constexpr std::size_t kMaxSetDirections = 6;
constexpr std::size_t kMaxConstraints = 24;

struct ExternalForceDriver {
  std::string name;
  std::string link;  // URDF link the wrench acts on (given in its frame, about its origin)
};

// A constraint set (docs/derivation.md, "Constraint sets"): `count` unit-force directions α
// acting on one link, given in that link's frame as [moment; force], each with its own setpoint
// β (α^T Ẍ_link = β). `fixed` holds the directions when the scene folds them into the code
// (then fixed.size() == count); empty: they are run-time inputs. An empty `link` is the
// chain's tip, as the scene's short forms (`constraints: 6`, `constraints: {directions}`) give
// it: then it is the only set, and its link acceleration is the solution's Ẍ_tip. A set that
// names its link (the scene's list form, any link of the chain) is *listed*: the solution
// reports its link's acceleration (set_acceleration).
//
// The directions act in frame A, fixed to the link at the pose `at` (scene key `at`, a URDF
// origin; identity: the link's own frame). A set between two links (a loop closure,
// docs/derivation.md (L1)) names the second, `relative_to`, and its frame B at `relative_at`: it
// asks α^T d/dt v_rel = β with v_rel = v_A − ^AX_B v_B, its wrench +α ν on A and the opposite on B.
struct ConstraintSet {
  std::string link;
  std::size_t count = 0;
  std::vector<spatial::Force<double>> fixed;
  model::Transform at;           // motion transform link -> A
  std::string relative_to;       // empty: the set holds A against the world
  model::Transform relative_at;  // motion transform relative_to -> B

  // A set on one link (empty: the tip) at its own frame, against the world.
  static ConstraintSet on(std::string link, std::size_t count, std::vector<spatial::Force<double>> fixed = {}) {
    ConstraintSet set;
    set.link = std::move(link);
    set.count = count;
    set.fixed = std::move(fixed);
    return set;
  }
  bool directions_fixed() const { return !fixed.empty(); }
  bool relative() const { return !relative_to.empty(); }
  // The link the set acts on: its own, or the chain's tip for the short forms.
  const std::string& link_in(const model::Chain& chain) const { return link.empty() ? chain.tip_link : link; }
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
  std::size_t constraints = 0;                         // Nc, all sets together
  // The sets, in order; their directions are numbered 0..Nc-1 in that order. Empty while
  // constraints > 0: one set of run-time directions on the tip (constraint_sets()).
  std::vector<ConstraintSet> sets;
  std::vector<Track> tracks;

  // `sets`, or the single tip set that an empty `sets` stands for.
  std::vector<ConstraintSet> constraint_sets() const;
  // Directions whose values are run-time inputs (the sets without fixed directions).
  std::size_t run_time_directions() const;
  // Sets that name their link (0 for the tip set of the short forms).
  std::size_t listed_sets() const;
  // Sets between two links (relative_to), each with a closure error.
  std::size_t loop_sets() const;

  // One track with everything (Alg. 1).
  void compose_all();
  // The bias and every instance on a track of its own (Alg. 2).
  void decompose_all();
  // Alg. 4 needs every external force on a pure external-force track.
  bool external_forces_separable() const;
};

// Throws InputError (naming `source`) if a name is unknown, a link is fixed to the base,
// a set is empty, holds more than six directions or repeats another's link, the sets' counts do
// not add up to Nc, or a driver instance sits on no track or on two. (An over-determining set is
// the scene's error, structurally_overdetermined; the solver itself copes: pivots drop.)
void validate(const DriverLayout& layout, const model::Chain& chain, const std::string& source);

// Why the sets' directions and the chain's coupled <mimic> joints (one direction each, M2) do not
// fit the kMaxConstraints directions a solve holds, "" where they do.
std::string too_many_directions(const DriverLayout& layout, const model::Chain& chain);

// Why a set between two links cannot be taken, "" where it can: its `relative_to` is not on the
// chain, or rides on the same body as its link (lumped together: they never move apart). The link
// itself is checked as every set's.
std::string relative_to_problem(const ConstraintSet& set, const model::Chain& chain);

// α of every direction, sets in order: the fixed ones as given, `run_time()` for the others
// (called once per run-time direction, in order).
template <class RunTime>
std::vector<spatial::Force<double>> directions_with(const DriverLayout& layout, RunTime&& run_time) {
  std::vector<spatial::Force<double>> alpha;
  for (const auto& set : layout.constraint_sets())
    for (std::size_t k = 0; k < set.count; ++k) alpha.push_back(set.directions_fixed() ? set.fixed[k] : run_time());
  return alpha;
}

// Per constraint direction, sets in order, the link its set acts on.
std::vector<std::string> direction_links(const DriverLayout& layout, const model::Chain& chain);

// A line per listed set: its link, its directions
// numbers (the indices of ν, β and set_acceleration), and the directions themselves when fixed
// or their place in the run-time α. For `sweepgen info` and the generated header.
std::vector<std::string> constraint_set_summary(const DriverLayout& layout);

// Whether the sets ask more of the robot than its joints can give at every state: a group of
// sets with more directions than the joints on the paths from the base to their links (the
// rank of their rows of the constraint Jacobian is at most that). Returns the explanation of
// the smallest such group, or "". Sets between two links are left out (their redundant
// directions are the rule: redundant_loop_warnings, solver/shared_body_sets.hpp).
std::string structurally_overdetermined(const std::vector<ConstraintSet>& sets, const model::Chain& chain);

}  // namespace sweepgen::solver
