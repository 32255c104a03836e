// Scale-invariant errors of one state against the referee (docs/stability.md, "Errors and
// condition numbers"): what the stability tests assert and `sweepgen report --stability`
// tabulates, in one place.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "model/chain.hpp"
#include "report/measure.hpp"

namespace sweepgen::report {

// ‖a − b‖∞ / ‖b‖∞ over the revolute joints and over the prismatic joints separately (their
// units differ), the larger of the two; a group whose b is 0 counts ‖a‖∞ (0 when exact). No
// floor in SI units: the figure is the same for a robot in any units. Infinity for NaN/Inf.
// `also`: further vectors whose size counts in the scale (the terms b is the sum of: where they
// cancel, rounding is relative to them, not to b).
double joint_relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b, const model::Chain& chain,
                            const std::vector<std::vector<Precise>>& also = {});

// ‖a − b‖∞ / ‖b‖∞ (ν: one unit for all entries).
double vector_relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b);

// κ = max(1, cond_s(E^A_cstr,0), 1 / min_i ρ_i): the amplification of rounding a backward-stable
// solve of this state cannot avoid (tests/test_stability.cpp, kErrorFactor).
inline double kappa(double cond_s, double min_rho_D) {
  return std::max({1.0, cond_s, min_rho_D > 0 ? 1 / min_rho_D : INFINITY});
}

// One variant's answer for one state, judged against the referee's.
struct StateJudgement {
  double qdd = 0, tau = 0, nu = 0;  // relative errors: q̈ against max(|q̈|, |q̈_free|), τcmd
                                    // against max(|τcmd|, |τff|, Truth::tau_constraint_terms),
                                    // ν against |ν|
  double cond_E = 1, rho_D = 1;     // cond_s(E^A_cstr,0), min_i ρ_i (solver/joint_inertia.hpp)
  double cond_M = 1;                // cond_2 of the referee's M(q) (inf where it locks a joint)
  // The variant's own constraint residual (measure.hpp, constraint_residual): whether its Ẍ_tip
  // meets α, β, whatever the referee says.
  double constraint_residual = 0;
  unsigned status = 0, exact_status = 0;  // the variant's and the referee's status bits
  bool finite = true;                     // every output of the variant is finite
  // Every output of the referee fits the scalar under test (|x| <= its max). Where one does not
  // (float: a thin rod's axial direction near a singularity needs a multiplier of 1e40 N), no
  // solver in that scalar can return it: the variant must say so with status_not_finite.
  bool representable = true;
  double kappa() const { return report::kappa(cond_E, rho_D); }
  double error() const { return std::max({qdd, tau, nu}); }
  // Neither the variant nor the referee dropped a direction or locked a joint: the errors are
  // rounding only, bounded by a multiple of eps κ.
  bool full_rank() const { return representable && status == 0 && exact_status == 0; }
};

// `largest`: the largest finite value of the scalar under test.
StateJudgement judge(const Outcome& outcome, const Truth& truth, const Problem& problem, const model::Chain& chain,
                     double largest);

}  // namespace sweepgen::report
