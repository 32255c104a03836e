// The constants of the generated code, checked before it is written: the trace folds the robot's
// and the scene's numbers (gravity, masses, inertias, origins) into constants, and numbers far
// outside a robot's range (gravity 1e308, a product of two 1e200 lengths) fold to Inf or NaN,
// which no literal spells and no solve could use.
#pragma once

#include <string>

#include "emit/function_plan.hpp"
#include "model/chain.hpp"
#include "solver/solver_model.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::emit {

// Throws InputError (the URDF, the generated function) naming the first quantity of `plan`'s
// functions, in the sweeps' order, that reads a constant which is not finite in `scalar`
// ("double" or "float"), and the numbers it was folded from: the scene's gravity and the range
// of the bodies' masses and rotational inertias.
void check_constants_finite(const symbolic::Trace& trace, const Plan& plan, const model::Chain& chain,
                            const solver::SolverOptions& options, const std::string& scalar);

}  // namespace sweepgen::emit
