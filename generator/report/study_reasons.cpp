#include "report/study_reasons.hpp"

#include <algorithm>
#include <limits>

#include "report/stability_measure.hpp"
#include "report/text_format.hpp"
#include "solver/state.hpp"

namespace sweepgen::report {
namespace {

// An error or residual this many ε of the row's scalar is worth a word: below it, rounding.
constexpr double kNoticeableEps = 1e4;

std::string of(std::size_t part, std::size_t whole) {
  return part == whole ? "every one of the " + std::to_string(whole) + " states"
                       : std::to_string(part) + " of " + std::to_string(whole) + " states";
}

// The κ up to which the tests judge a scalar's results against a multiple of ε κ
// (docs/stability.md, "Float: domain of validity"; tests/support/rounding_bound.hpp).
double domain_kappa(const std::string& scalar) { return scalar == "float" ? 1e3 : 1e8; }

// Why a direction dropped on this family is or is not expected (extreme_states.hpp: the kinds).
std::pair<std::string, bool> why_dropped(const std::string& family) {
  if (family == "redundant")
    return {"expected: the family repeats a direction and adds a dependent one, so they cannot all be met", true};
  if (family == "singular") return {"expected: at q = 0 the directions are dependent", true};
  if (family == "near_singular")
    return {"expected: κ goes beyond the pivot tolerance of the scalar (1000 ε) here, and a direction that close to "
            "dependent is dropped rather than solved into noise",
            true};
  return {"not expected on these states: report it", false};
}

struct Finding {
  std::string text;
  bool expected;
};

// The findings of one row on one family.
std::vector<Finding> findings(const VariantStudy& v, const std::string& family) {
  const double eps = epsilon_of(v.scalar), domain = domain_kappa(v.scalar);
  const auto ratio = [&](double value, const StatePoint& p) { return value / (eps * std::max(1.0, p.kappa)); };
  std::size_t states = 0, dropped = 0, referee_dropped = 0, locked = 0, not_finite = 0, saturated = 0;
  std::size_t beyond = 0, at_clamp = 0, outside = 0, large = 0, met = 0, gives_way = 0, unmet = 0;
  double worst_beyond = 0, worst_clamp = 0, worst_outside = 0, worst_error = 0, worst_met = 0, worst_unmet = 0;
  double kappa_max = 1;
  for (const StatePoint& p : v.states) {
    if (p.family != family) continue;
    ++states;
    if (p.status & solver::status_constraint_rank_deficient) ++dropped;
    else if (p.referee_status & solver::status_constraint_rank_deficient) ++referee_dropped;
    if ((p.status | p.referee_status) & solver::status_joint_inertia_singular) ++locked;
    if (p.status & solver::status_not_finite) ++not_finite;
    if (p.status & solver::status_saturated) ++saturated;
    if (!p.judged) continue;
    kappa_max = std::max(kappa_max, p.kappa);
    const double r = ratio(p.error(), p);
    const bool clamp = v.clamps && ((p.status | p.referee_status) & solver::status_saturated);
    if (r > kErrorBoundEpsKappa && p.kappa > domain) ++outside, worst_outside = std::max(worst_outside, r);
    else if (r > kErrorBoundEpsKappa && clamp) ++at_clamp, worst_clamp = std::max(worst_clamp, r);
    else if (r > kErrorBoundEpsKappa) ++beyond, worst_beyond = std::max(worst_beyond, r);
    else if (p.error() > kNoticeableEps * eps) ++large, worst_error = std::max(worst_error, p.error());
    if (p.residual <= kNoticeableEps * eps) continue;
    if (ratio(p.residual, p) <= kErrorBoundEpsKappa) ++met, worst_met = std::max(worst_met, p.residual);
    else if (!v.gives_way_because.empty()) ++gives_way, worst_unmet = std::max(worst_unmet, p.residual);
    else ++unmet, worst_unmet = std::max(worst_unmet, p.residual);
  }
  const std::string bound = format("%.0f", kErrorBoundEpsKappa) + " ε κ";
  const std::string not_expected = "not expected: beyond the bound the stability suite asserts (docs/stability.md): report it";
  std::vector<Finding> out;
  if (dropped > 0) {
    const auto [why, expected] = why_dropped(family);
    out.push_back({"dropped a constraint direction (status_constraint_rank_deficient) on " + of(dropped, states) +
                       ", so those states are not judged: " + why,
                   expected});
  }
  if (referee_dropped > 0)
    out.push_back({"not judged on " + of(referee_dropped, states) + ": the referee dropped a direction that this row " +
                       (v.keeps_every_direction ? "solves for (it reports no dropped direction)"
                                                : "kept (a pivot at the tolerance, decided the other way by rounding)") +
                       ", so the two answer different problems: expected",
                   true});
  if (locked > 0)
    out.push_back({"a joint locked (J1: its articulated inertia D_i below tolerance) on " + of(locked, states) +
                       ", not judged: expected only for a joint without inertia about its axis (`sweepgen info` lists "
                       "the masses)",
                   false});
  if (not_finite > 0)
    out.push_back({"returned a value that is not finite on " + of(not_finite, states) + ": not expected: report it", false});
  if (saturated > 0)
    out.push_back({"clamped torques at their effort limits (status_saturated) on " + of(saturated, states) +
                       ": expected, the policy's job where the motion asks more than the limits give",
                   true});
  if (outside > 0)
    out.push_back({"error above " + bound + " on " + std::to_string(outside) + " judged states where κ is beyond " +
                       v.scalar + "'s domain, κ > " + format("%.0e", domain) + " (worst " + format("%.3g", worst_outside) +
                       " ε κ): expected, the suite asserts nothing there (docs/stability.md, \"Float: domain of validity\")",
                   true});
  if (at_clamp > 0)
    out.push_back({"error above " + bound + " on " + std::to_string(at_clamp) + " judged states where a torque is at its "
                       "limit (worst " + format("%.3g", worst_clamp) + " ε κ): expected, rounding decides there whether "
                       "it clamps, and this row and its referee answer on either side of the clamp",
                   true});
  if (beyond > 0) {
    const std::string text = "error above " + bound + " on " + std::to_string(beyond) + " judged states (worst " +
                             format("%.3g", worst_beyond) + " ε κ)";
    if (v.unbounded_because.empty()) out.push_back({text + ": " + not_expected, false});
    else out.push_back({text + ": expected for this row: " + v.unbounded_because, true});
  }
  if (large > 0)
    out.push_back({"error up to " + scientific(worst_error) + " on " + std::to_string(large) + " judged states, within " +
                       bound + " (κ up to " + format("%.1e", kappa_max) + "): expected, the problem is that ill-conditioned",
                   true});
  if (met > 0)
    out.push_back({"constraint residual up to " + scientific(worst_met) + " on " + std::to_string(met) +
                       " judged states, within " + bound + ": expected, the constraints are met to rounding times κ",
                   true});
  if (gives_way > 0)
    out.push_back({"constraint residual up to " + scientific(worst_unmet) + " on " + std::to_string(gives_way) +
                       " judged states: expected, " + v.gives_way_because,
                   true});
  if (unmet > 0) {
    const std::string text = "constraint residual up to " + scientific(worst_unmet) + " on " + std::to_string(unmet) +
                             " judged states, above " + bound;
    if (v.unbounded_because.empty()) out.push_back({text + ": " + not_expected, false});
    else out.push_back({text + ": expected for this row: " + v.unbounded_because, true});
  }
  return out;
}

}  // namespace

std::vector<Reason> study_reasons(const SceneStudy& study) {
  std::vector<Reason> reasons;
  for (const auto& [family, count] : study.families)
    for (const VariantStudy& v : study.variants) {
      if (!v.note.empty() || v.referee) continue;
      for (const Finding& f : findings(v, family)) {
        const auto same = std::find_if(reasons.begin(), reasons.end(), [&](const Reason& r) {
          return r.family == family && r.text == f.text;
        });
        if (same != reasons.end()) {
          same->variants.push_back(v.name);
        } else {
          reasons.push_back({family, f.text, f.expected, {v.name}});
        }
      }
    }
  return reasons;
}

}  // namespace sweepgen::report
