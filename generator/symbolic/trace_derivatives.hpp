// Runs the reference sweeps with the dual scalar over the symbolic one (solver/dual_scalar.hpp,
// docs/derivation.md (D1)–(D3)): the values and the tangents along (D2)'s columns become nodes
// of one graph, folded and shared like the values, from which the generated derivative functions
// are written. The equations are the solver's; nothing here restates them.
#pragma once

#include "solver/derivative_seeds.hpp"
#include "symbolic/trace.hpp"

namespace sweepgen::symbolic {

// Per differentiable policy of `request` (solver::differentiable), group = the policy's name,
// fields qdd, nu, tau_cmd, the Jacobians of those `outputs` selects, d_qdd, d_nu, d_tau_cmd
// (row-major over (D2)'s columns), dropped_pivots and locked_joints (the status); kinematics and
// articulated fields name and anchor the values they are computed from. Inputs as trace_solver's.
Trace trace_derivatives(const model::Chain& chain, const TraceRequest& request,
                        const solver::DerivativeOutputs& outputs = {});

}  // namespace sweepgen::symbolic
