#include "report/study_reasons.hpp"

#include <algorithm>
#include <cmath>
#include <map>

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

// An error or residual below √ε keeps half the digits or more: not worth a word.
double noticeable(const std::string& scalar) { return std::sqrt(epsilon_of(scalar)); }

std::string error_bound() { return format("%.0f", kErrorBoundEpsKappa) + " ε κ"; }

// Where a judged state's error stands against the bound the stability suite asserts: the bullets
// per family and the notes beside the summary table sort states alike.
enum class ErrorClass {
  small,            // below √ε: not worth a word
  ill_conditioned,  // within the bound, large because κ is
  row_unbounded,    // above the bound on a row the bound does not hold for (VariantStudy::unbounded_because)
  outside_domain,   // above the bound where κ is beyond the scalar's domain
  at_clamp,         // above the bound where a torque is at its limit
  beyond_bound,     // above the bound for none of these reasons
};

// A judged state's error in units of ε κ.
double in_eps_kappa(const VariantStudy& v, const StatePoint& p) {
  return p.error() / (epsilon_of(v.scalar) * std::max(1.0, p.kappa));
}

// A row's own reason (KDL, the dense KKT) goes first: it is why that row reaches an error of 1 where
// the project's solvers, on the same states, stay within the bound.
ErrorClass classify(const VariantStudy& v, const StatePoint& p) {
  if (in_eps_kappa(v, p) <= kErrorBoundEpsKappa)
    return p.error() > noticeable(v.scalar) ? ErrorClass::ill_conditioned : ErrorClass::small;
  if (!v.unbounded_because.empty()) return ErrorClass::row_unbounded;
  if (p.kappa > domain_kappa(v.scalar)) return ErrorClass::outside_domain;
  if (v.clamps && ((p.status | p.referee_status) & solver::status_saturated)) return ErrorClass::at_clamp;
  return ErrorClass::beyond_bound;
}

// What an error of class `c` says: where it happens (for the classes above the bound, the words
// after "error above 100 ε κ") and why, with whether that is expected.
struct ErrorWhy {
  std::string where;
  Finding why;
};
ErrorWhy error_why(ErrorClass c, const VariantStudy& v) {
  switch (c) {
    case ErrorClass::row_unbounded: return {"", {"expected for this row: " + v.unbounded_because, true}};
    case ErrorClass::outside_domain:
      return {" where κ is beyond " + v.scalar + "'s domain, κ > " + format("%.0e", domain_kappa(v.scalar)),
              {"expected, the suite asserts nothing there (docs/stability.md, \"Float: domain of validity\")", true}};
    case ErrorClass::at_clamp:
      return {" where a torque is at its limit",
              {"expected, rounding decides there whether it clamps, and this row and its referee answer on either "
               "side of the clamp",
               true}};
    case ErrorClass::beyond_bound:
      return {"", {"not expected: beyond the bound the stability suite asserts (docs/stability.md): report it", false}};
    case ErrorClass::ill_conditioned: return {"", {"expected, the problem is that ill-conditioned", true}};
    case ErrorClass::small: break;
  }
  return {"", {"", true}};
}

// Why a row's constraint residual is above √ε, which it always may be: the suite bounds errors.
std::string residual_why(const VariantStudy& v) {
  if (!v.gives_way_because.empty()) return v.gives_way_because;
  if (!v.unbounded_because.empty()) return "for this row: " + v.unbounded_because;
  return "the constraint is met to the rounding of the terms it balances (large on fast or huge-force states, or "
         "where κ is large); the suite bounds the errors of q̈, τcmd and ν, not the residual";
}

// The errors of one class on one family's judged states.
struct ClassTally {
  std::size_t states = 0;
  double worst_ratio = 0;  // error / (ε κ)
  double worst_error = 0;
};

// What one row did on one family's states, counted.
struct Tally {
  std::size_t states = 0, held_back = 0, dropped_expected = 0, dropped_unexpected = 0, referee_dropped = 0, locked = 0,
              not_finite = 0, saturated = 0, residual = 0;
  std::map<ErrorClass, ClassTally> errors;  // the judged states whose error is worth a word, by class
  double kappa_dropped = 1, worst_residual = 0, kappa_max = 1;
};

Tally tally(const VariantStudy& v, const std::string& family) {
  const double eps = epsilon_of(v.scalar);
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
    const ErrorClass c = classify(v, p);
    if (c != ErrorClass::small) {
      ClassTally& e = t.errors[c];
      ++e.states;
      e.worst_ratio = std::max(e.worst_ratio, in_eps_kappa(v, p));
      e.worst_error = std::max(e.worst_error, p.error());
    }
    if (p.residual > noticeable(v.scalar)) ++t.residual, t.worst_residual = std::max(t.worst_residual, p.residual);
  }
  return t;
}

// The findings of one row on one family.
std::vector<Finding> findings(const VariantStudy& v, const std::string& family) {
  const Tally t = tally(v, family);
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
  for (const ErrorClass c :
       {ErrorClass::outside_domain, ErrorClass::at_clamp, ErrorClass::row_unbounded, ErrorClass::beyond_bound}) {
    const auto e = t.errors.find(c);
    if (e == t.errors.end()) continue;
    const ErrorWhy w = error_why(c, v);
    out.push_back({"error above " + error_bound() + " on " + judged_states(e->second.states) + w.where + " (worst " +
                       format("%.3g", e->second.worst_ratio) + " ε κ): " + w.why.text,
                   w.why.expected});
  }
  if (const auto e = t.errors.find(ErrorClass::ill_conditioned); e != t.errors.end())
    out.push_back({"error up to " + scientific(e->second.worst_error) + " on " + judged_states(e->second.states) +
                       ", within " + error_bound() + " (κ up to " + format("%.1e", t.kappa_max) + "): " +
                       error_why(ErrorClass::ill_conditioned, v).why.text,
                   true});
  if (t.residual > 0)
    out.push_back({"constraint residual up to " + scientific(t.worst_residual) + " on " + judged_states(t.residual) +
                       ": expected, " + residual_why(v),
                   true});
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

RowReasons row_reasons(const VariantStudy& v) {
  const StatePoint* worst_error = nullptr;
  const StatePoint* worst_residual = nullptr;
  for (const StatePoint& p : v.states) {
    if (!p.judged) continue;
    if (!worst_error || p.error() > worst_error->error()) worst_error = &p;
    if (!worst_residual || p.residual > worst_residual->residual) worst_residual = &p;
  }
  RowReasons reasons;
  if (!worst_error) return reasons;
  const ErrorClass c = classify(v, *worst_error);
  const ErrorWhy w = error_why(c, v);
  if (c == ErrorClass::ill_conditioned)
    reasons.error = {"error within " + error_bound() + ": " + w.why.text, w.why.expected};
  else if (c != ErrorClass::small)
    reasons.error = {"error above " + error_bound() + w.where + ": " + w.why.text, w.why.expected};
  if (worst_residual->residual > noticeable(v.scalar))
    reasons.residual = {"constraint residual above √ε: expected, " + residual_why(v), true};
  return reasons;
}

}  // namespace sweepgen::report
