// The constants of the generated code, checked before it is written: the trace folds the robot's
// and the scene's numbers (gravity, masses, inertias, origins) into constants, and numbers far
// outside a robot's range (gravity 1e308, a product of two 1e200 lengths) fold to NaN, or
// overflow the scalar (1e60 is a float's Inf), which no literal spells and no solve could use.
// (An Inf of the trace itself is a value: an unlimited joint's effort bound, HUGE_VAL.)
#pragma once

#include <string>

#include "emit/function_plan.hpp"
#include "model/chain.hpp"
#include "solver/solver_model.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::emit {

// Throws InputError (the URDF, the generated function) naming the first quantity of `plan`'s
// functions, in the sweeps' order, that reads a constant which is NaN or a finite number beyond
// `scalar`'s range ("double" or "float"), and the numbers it was folded from: the scene's gravity and the range
// of the bodies' masses and rotational inertias.
void check_constants_finite(const symbolic::Trace& trace, const Plan& plan, const model::Chain& chain,
                            const solver::SolverOptions& options, const std::string& scalar);

}  // namespace sweepgen::emit
