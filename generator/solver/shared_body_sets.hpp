// Constraint sets that act on one rigid body: sets on links that the same moving body carries
// (a link fixed to another, or behind a locked joint, such as the two fingers of a gripper that
// is not on a tip's path). The scene is valid, but the sets' directions then constrain one body's
// spatial acceleration together: more than six, or forces at several points (three at each of
// two points span five), are dependent, and the solve reports status_constraint_rank_deficient
// wherever they are. `sweepgen generate` and `info` warn about it before any solve.
// Likewise a set between two links with more directions than the joints between them: redundant
// loop directions are the rule (a planar loop closed by a 3-D or 6-D set), so the scene is not
// refused as an over-determining set on one link is (structurally_overdetermined); the surplus
// is dropped at every state, with status_constraint_rank_deficient.
#pragma once

#include <string>
#include <vector>

#include "model/chain.hpp"
#include "solver/drivers.hpp"

namespace sweepgen::solver {

// One warning per body that carries the links of two or more sets: the sets, the body, and why.
std::vector<std::string> shared_body_warnings(const std::vector<ConstraintSet>& sets, const model::Chain& chain);

// One warning per set between two links that holds more directions than the joints between them.
std::vector<std::string> redundant_loop_warnings(const std::vector<ConstraintSet>& sets, const model::Chain& chain);

}  // namespace sweepgen::solver
