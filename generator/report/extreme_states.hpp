// The states of the numerical-stability suite (docs/stability.md, "States"): seeded, in the
// report's Problem form (so that the referee, the generated code and KDL all take them).
//
//   nominal      q within the limits, q̇ within the velocity limits, τff up to half the effort
//                limit, wrenches of 2 N m / 20 N, random unit α, β in [-3, 3]
//   fast         as nominal with |q̇_i| = 100 rad/s (prismatic: 100 length-scale/s), random signs
//   huge_force   as nominal with wrenches of 1e6 N and 1e6 N x length-scale
//   singular     q at a configuration where the tip's six directions are singular (stretched
//                arm, aligned wrist axes), α the six unit directions (Nc = 6 on a 6-DOF arm at a
//                singularity), then q + δ u for δ = 1e-2 ... 1e-10 (near-singular)
//   redundant    α_2 = α_1 (a repeated direction) and α_3 = (α_1 + α_2') / |.| (linearly dependent)
// Directions fixed by the scene are kept as they are. The length scale (for prismatic speeds
// and moments) is the mean joint offset |r| of the chain.
#pragma once

#include <string>
#include <vector>

#include "report/measure.hpp"

namespace sweepgen::report {

struct LabelledProblem {
  std::string kind;  // nominal, fast, huge_force, singular, near_singular, redundant
  double delta = 0;  // near_singular: distance from the singular configuration
  Problem problem;
};

// `per_kind` random states of each random kind; the singular kinds only when `singular_q` is
// not empty (one state at it, one per δ).
std::vector<LabelledProblem> extreme_states(const scene::Scene& s, const model::Chain& chain, std::size_t per_kind,
                                            const std::vector<double>& singular_q, unsigned long long seed);

// Mean |r| of the chain's joint offsets (> 0): the length that scales prismatic speeds and moments.
double length_scale(const model::Chain& chain);

}  // namespace sweepgen::report
