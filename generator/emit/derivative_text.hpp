// The text of the derivative functions (scene key derivatives; docs/derivation.md, D1–D8): their
// flat output's order, its packing from a Derivatives struct, the NaN/Inf check of the results,
// and the line `sweepgen info` prints. Filled into templates/ by solver_emitter.
#pragma once

#include <cstddef>
#include <string>

#include "solver/derivative_seeds.hpp"

namespace sweepgen::emit {

// The order of the flat output of derivatives_<policy>_flat (`columns`: the scene's, D2).
std::string derivative_flat_out(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs);
// That output written from a Derivatives struct.
std::string pack_derivatives(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs);
// The Jacobians the derivative functions return and those left out, one line for `sweepgen info`.
std::string derivatives_line(const solver::DerivativeOutputs& outputs, std::size_t nc);
// NaN/Inf among the results (scene: check_inputs): one in an input the results depend on reaches them.
std::string check_derivatives(const solver::DerivativeColumns& columns, const solver::DerivativeOutputs& outputs);

}  // namespace sweepgen::emit
