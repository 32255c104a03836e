// One line for the generated header and `sweepgen info`: on which joints the joint-inertia test
// (J1) stays, on which the model's bounds drop it (J2), and where S_i^T P_i^T = 0 is written
// exactly; per emitted scalar where their tolerances decide differently.
#pragma once

#include <string>
#include <vector>

#include "model/chain.hpp"
#include "solver/solver_model.hpp"

namespace sweepgen::emit {

// `epsilons`: machine epsilon of each emitted scalar, named by `scalars`.
std::string joint_inertia_note(const model::Chain& chain, const solver::DriverLayout& layout,
                               const solver::SolverOptions& options, const std::vector<std::string>& scalars,
                               const std::vector<double>& epsilons);

}  // namespace sweepgen::emit
