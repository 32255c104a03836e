#include "report/study_reasons.hpp"

#include <algorithm>
#include <cmath>

#include "report/stability_measure.hpp"
#include "report/text_format.hpp"
#include "solver/state.hpp"

namespace sweepgen::report {
namespace {

// "3 of 40 states", "every one of the 40 states".
std::string of(std::size_t part, std::size_t whole) {
  return part == whole ? "every one of the " + std::to_string(whole) + " states"
                       : std::to_string(part) + " of " + std::to_string(whole) + " states";
}
std::string judged_states(std::size_t count) {
  return std::to_string(count) + " judged state" + (count == 1 ? "" : "s");
}

// The κ up to which the tests judge a scalar's results against a multiple of ε κ
// (docs/stability.md, "Float: domain of validity"; tests/support/rounding_bound.hpp).
double domain_kappa(const std::string& scalar) { return scalar == "float" ? 1e3 : 1e8; }

// A direction is dropped where its pivot falls below 1000 ε of its diagonal (README, "Singular
// constraints"), which takes κ of about 1 / (1000 ε) or more; within a factor of ten of that (κ
// measures the whole matrix, the pivot one direction), a dropped direction is the pivot test at work.
bool beyond_pivot_tolerance(double kappa, double eps) { return kappa * 1e4 * eps >= 1; }

// Families whose directions are dependent at every state (extreme_states.hpp: the kinds).
std::string dependent_by_construction(const std::string& family) {
  if (family == "redundant") return "the family repeats a direction and adds a dependent one, so they cannot all be met";
  if (family == "singular") return "at q = 0 the directions are dependent";
  return "";
}

struct Finding {
  std::string text;
  bool expected;
};

// What one row did on one family's states, counted.
struct Tally {
  std::size_t states = 0, held_back = 0, dropped_expected = 0, dropped_unexpected = 0, referee_dropped = 0, locked = 0,
              not_finite = 0, saturated = 0, beyond = 0, at_clamp = 0, outside = 0, large = 0, residual = 0;
  double kappa_dropped = 1, worst_beyond = 0, worst_clamp = 0, worst_outside = 0, worst_error = 0,
         worst_residual = 0, kappa_max = 1;
};

Tally tally(const VariantStudy& v, const std::string& family) {
  const double eps = epsilon_of(v.scalar), domain = domain_kappa(v.scalar);
  // An error or residual below √ε keeps half the digits or more: not worth a word.
  const double noticeable = std::sqrt(eps);
  const bool dependent = !dependent_by_construction(family).empty();
  Tally t;
  for (const StatePoint& p : v.states) {
    if (p.family != family) continue;
    ++t.states;
    if ((p.status & solver::status_constraint_rank_deficient) && v.keeps_every_direction) {
      ++t.held_back;
    } else if (p.status & solver::status_constraint_rank_deficient) {
      if (dependent || beyond_pivot_tolerance(p.kappa, eps)) ++t.dropped_expected, t.kappa_dropped = std::max(t.kappa_dropped, p.kappa);
      else ++t.dropped_unexpected;
    } else if (p.referee_status & solver::status_constraint_rank_deficient) {
      ++t.referee_dropped;
    }
    if ((p.status | p.referee_status) & solver::status_joint_inertia_singular) ++t.locked;
    if (p.status & solver::status_not_finite) ++t.not_finite;
    if (p.status & solver::status_saturated) ++t.saturated;
    if (!p.judged) continue;
    t.kappa_max = std::max(t.kappa_max, p.kappa);
    const double ratio = p.error() / (eps * std::max(1.0, p.kappa));
    const bool clamp = v.clamps && ((p.status | p.referee_status) & solver::status_saturated);
    if (ratio > kErrorBoundEpsKappa && p.kappa > domain) ++t.outside, t.worst_outside = std::max(t.worst_outside, ratio);
    else if (ratio > kErrorBoundEpsKappa && clamp) ++t.at_clamp, t.worst_clamp = std::max(t.worst_clamp, ratio);
    else if (ratio > kErrorBoundEpsKappa) ++t.beyond, t.worst_beyond = std::max(t.worst_beyond, ratio);
    else if (p.error() > noticeable) ++t.large, t.worst_error = std::max(t.worst_error, p.error());
    if (p.residual > noticeable) ++t.residual, t.worst_residual = std::max(t.worst_residual, p.residual);
  }
  return t;
}

// The findings of one row on one family.
std::vector<Finding> findings(const VariantStudy& v, const std::string& family) {
  const Tally t = tally(v, family);
  const std::string bound = format("%.0f", kErrorBoundEpsKappa) + " ε κ";
  std::vector<Finding> out;
  const auto dropped = [&](std::size_t count) {
    return "dropped a constraint direction (status_constraint_rank_deficient) on " + of(count, t.states) +
           ", not judged there: ";
  };
  if (t.dropped_expected > 0) {
    const std::string dependent = dependent_by_construction(family);
    out.push_back({dropped(t.dropped_expected) + "expected: " +
                       (!dependent.empty() ? dependent
                                           : "κ (up to " + format("%.1e", t.kappa_dropped) + ") goes beyond what " +
                                                 v.scalar + "'s pivot tolerance, 1000 ε, resolves, and a direction "
                                                 "that close to dependent is dropped rather than solved into noise"),
                   true});
  }
  if (t.held_back > 0)
    out.push_back({"raised status_constraint_rank_deficient on " + of(t.held_back, t.states) + ", not judged there: "
                       "expected, the damped factorisation keeps every direction and says so where the damping visibly "
                       "held a multiplier back (a direction near dependent, or one asking for the impossible; README, "
                       "\"Singular constraints\")",
                   true});
  if (t.dropped_unexpected > 0)
    out.push_back({dropped(t.dropped_unexpected) + "not expected where κ is this small: report it", false});
  if (t.referee_dropped > 0)
    out.push_back({"not judged on " + of(t.referee_dropped, t.states) + ": the referee dropped a direction that this " +
                       "row " +
                       (v.keeps_every_direction ? "solves for (it reports no dropped direction)"
                                                : "kept (a pivot at the tolerance, decided the other way by rounding)") +
                       ", so the two answer different problems: expected",
                   true});
  if (t.locked > 0)
    out.push_back({"a joint locked (J1: its articulated inertia D_i below tolerance) on " + of(t.locked, t.states) +
                       ", not judged there: expected only for a joint without inertia about its axis (`sweepgen info` "
                       "lists the masses)",
                   false});
  if (t.not_finite > 0)
    out.push_back({"returned a value that is not finite on " + of(t.not_finite, t.states) + ": not expected: report it",
                   false});
  if (t.saturated > 0)
    out.push_back({"clamped torques at their effort limits (status_saturated) on " + of(t.saturated, t.states) +
                       ": expected, the policy's job where the motion asks more than the limits give",
                   true});
  if (t.outside > 0)
    out.push_back({"error above " + bound + " on " + judged_states(t.outside) + " where κ is beyond " + v.scalar +
                       "'s domain, κ > " + format("%.0e", domain_kappa(v.scalar)) + " (worst " +
                       format("%.3g", t.worst_outside) + " ε κ): expected, the suite asserts nothing there "
                       "(docs/stability.md, \"Float: domain of validity\")",
                   true});
  if (t.at_clamp > 0)
    out.push_back({"error above " + bound + " on " + judged_states(t.at_clamp) + " where a torque is at its limit "
                       "(worst " + format("%.3g", t.worst_clamp) + " ε κ): expected, rounding decides there whether it "
                       "clamps, and this row and its referee answer on either side of the clamp",
                   true});
  if (t.beyond > 0) {
    const std::string text = "error above " + bound + " on " + judged_states(t.beyond) + " (worst " +
                             format("%.3g", t.worst_beyond) + " ε κ)";
    if (v.unbounded_because.empty())
      out.push_back({text + ": not expected: beyond the bound the stability suite asserts (docs/stability.md): report it",
                     false});
    else
      out.push_back({text + ": expected for this row: " + v.unbounded_because, true});
  }
  if (t.large > 0)
    out.push_back({"error up to " + scientific(t.worst_error) + " on " + judged_states(t.large) + ", within " + bound +
                       " (κ up to " + format("%.1e", t.kappa_max) + "): expected, the problem is that ill-conditioned",
                   true});
  if (t.residual > 0) {
    std::string why = !v.gives_way_because.empty() ? v.gives_way_because
                      : !v.unbounded_because.empty()
                          ? "for this row: " + v.unbounded_because
                          : "the constraint is met to the rounding of the terms it balances (large on fast or "
                            "huge-force states, or where κ is large); the suite bounds the errors of q̈, τcmd and ν, "
                            "listed above where they are large, not the residual";
    out.push_back({"constraint residual up to " + scientific(t.worst_residual) + " on " + judged_states(t.residual) +
                       ": expected, " + why,
                   true});
  }
  return out;
}

}  // namespace

std::vector<Reason> study_reasons(const SceneStudy& study) {
  std::vector<Reason> reasons;
  for (const auto& family_count : study.families) {
    // Not a structured binding: C++17 lambdas cannot capture one (clang refuses).
    const auto& family = family_count.first;
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
  }
  return reasons;
}

}  // namespace sweepgen::report
