#include "report/study.hpp"

#include <algorithm>
#include <limits>
#include <map>

#include "report/compiled_solver.hpp"
#include "report/dense_kkt_row.hpp"
#include "report/extreme_states.hpp"
#include "report/kdl_row.hpp"
#include "report/stability_errors.hpp"
#include "report/stability_measure.hpp"
#include "report/text_format.hpp"
#include "solver/solver_sweep.hpp"

namespace sweepgen::report {
namespace {

using solver::ConstraintFactorisation;
using solver::Policy;

// A singular configuration is one where cond_s(E^A_cstr,0) exceeds this: far beyond any state
// the nominal families reach, so that the sweep away from it spans the κ range.
constexpr double kSingularCondition = 1e10;

// The referee a variant is judged against: the problem it solves and the scalar whose
// tolerances decide ranks (with_tolerance_factor).
struct Referee {
  Policy policy = Policy::original;
  ConstraintFactorisation factorisation = ConstraintFactorisation::pivoted_ldlt;
  std::string scalar = "double";
  bool operator<(const Referee& o) const {
    return std::tie(policy, factorisation, scalar) < std::tie(o.policy, o.factorisation, o.scalar);
  }
};

struct Measured {
  VariantStudy study;
  VariantResult result;
  Referee referee;
};

std::string factorisation_label(ConstraintFactorisation f) {
  return f == ConstraintFactorisation::damped ? "damped LDLᵀ" : "pivoted LDLᵀ";
}

std::string policy_label(Policy p) {
  switch (p) {
    case Policy::original: return "Alg. 3 (original)";
    case Policy::prioritize_external: return "Alg. 4 (external forces prioritised)";
    case Policy::saturate: return "Eq. 1 (τctrl saturated)";
    case Policy::saturate_exact: return "exact saturation (τcmd clamped)";
  }
  return "";
}

// Why a row of this policy and factorisation does not meet the constraint to rounding, by design
// ("" where it does; docs/derivation.md, section 5).
std::string gives_way_because(Policy p, ConstraintFactorisation f) {
  if (p == Policy::prioritize_external)
    return "Alg. 4 leaves the external forces out of the constraint's reaction and adds their full effect on top, so "
           "the constraint gives way where they act (docs/derivation.md, section 5)";
  if (p == Policy::saturate || p == Policy::saturate_exact)
    return "where a torque is clamped at its effort limit, the constrained motion is out of reach";
  if (f == ConstraintFactorisation::damped)
    return "the damped factorisation solves (E + t I): ν stays bounded and the constraint is met to about t cond_s(E) "
           "(scene key constraint_factorisation)";
  return "";
}

scene::Scene with_factorisation(scene::Scene s, ConstraintFactorisation f) {
  s.constraint_factorisation = f;
  return s;
}

double largest_of(const std::string& scalar) {
  return scalar == "float" ? std::numeric_limits<float>::max() : std::numeric_limits<double>::max();
}

// The scene's policies with the original one first (the float entry point is the original's).
std::vector<Policy> policies_of(const scene::Scene& s) {
  std::vector<Policy> policies{Policy::original};
  for (const Policy p : s.policies)
    if (p != Policy::original) policies.push_back(p);
  return policies;
}

// The states, with the near-singular sweep only where q = 0 is singular for the scene's
// directions (the stretched pose of most arms; checked, not assumed).
std::vector<LabelledProblem> study_states(const scene::Scene& s, const model::Chain& chain,
                                          const StudyOptions& options, std::string& singular_note) {
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  std::vector<LabelledProblem> states =
      extreme_states(s, chain, options.states_per_family, std::vector<double>(nc > 0 ? n : 0, 0.0), options.seed);
  if (nc == 0) {
    singular_note = "no constraint directions: no near-singular sweep";
    return states;
  }
  const auto singular = std::find_if(states.begin(), states.end(), [](const auto& x) { return x.kind == "singular"; });
  const double cond =
      precise_reference(s, chain, {singular->problem}, s.solver_options(), Policy::original, false).front().cond_scaled;
  if (cond >= kSingularCondition) {
    singular_note = "near-singular sweep: q = 0 + δ u, δ = 1e-2 … 1e-10 (cond_s(E) at q = 0: " + scientific(cond) + ")";
    return states;
  }
  singular_note = "q = 0 is not singular for this scene's directions (cond_s(E) = " + scientific(cond) +
                  " < " + scientific(kSingularCondition) + "): no near-singular sweep";
  states.erase(std::remove_if(states.begin(), states.end(),
                              [](const auto& x) { return x.kind == "singular" || x.kind == "near_singular"; }),
               states.end());
  return states;
}

// The status bits after which a variant's answer is not the referee's problem's any more (a
// direction dropped, a joint locked, a value not finite): such states are counted, not judged.
// A saturating policy's clamp is its problem, not a failure: those states are judged.
constexpr unsigned kNotJudged =
    solver::status_constraint_rank_deficient | solver::status_joint_inertia_singular | solver::status_not_finite;

bool judged(const StateJudgement& j) {
  return j.representable && j.finite && ((j.status | j.exact_status) & kNotJudged) == 0;
}

// The statistics of the states of `family` ("all": every state).
FamilyErrors errors_of(const std::string& family, const std::vector<StatePoint>& states) {
  FamilyErrors e;
  e.family = family;
  std::vector<double> errors, residuals;
  for (const StatePoint& p : states) {
    if (family != "all" && p.family != family) continue;
    ++e.states;
    if (p.status != 0) ++e.status_raised;
    if (!p.judged) continue;
    errors.push_back(p.error());
    residuals.push_back(p.residual);
  }
  e.judged = errors.size();
  if (!errors.empty()) {
    e.median = quantile(errors, 0.5);
    e.p99 = quantile(errors, 0.99);
    e.max = *std::max_element(errors.begin(), errors.end());
    e.max_residual = *std::max_element(residuals.begin(), residuals.end());
  }
  return e;
}

// Times and errors of one measured variant, per family and overall.
void summarise(Measured& m, const std::vector<Truth>& truth, const std::vector<LabelledProblem>& states,
               const std::vector<std::pair<std::string, std::size_t>>& families, const model::Chain& chain) {
  VariantStudy& v = m.study;
  v.note = m.result.note;
  if (!v.note.empty()) return;
  const std::vector<double>& ns = m.result.ns_per_call;
  if (!ns.empty()) {
    v.ns_median = quantile(ns, 0.5);
    v.ns_p99 = quantile(ns, 0.99);
    v.ns_max = *std::max_element(ns.begin(), ns.end());
  }
  if (v.referee) return;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const StateJudgement j = judge(m.result.outcomes[k], truth[k], states[k].problem, chain, largest_of(v.scalar));
    v.states.push_back({states[k].kind, j.kappa(), j.qdd, j.tau, j.nu, j.constraint_residual, j.status, j.exact_status,
                        judged(j)});
  }
  for (const auto& [family, count] : families) v.families.push_back(errors_of(family, v.states));
  v.all = errors_of("all", v.states);
}

// The largest κ below which float answers every state: meets kFloatGoal where judged, and drops no
// direction, locks no joint and returns nothing non-finite (its pivot tolerance, 1000 eps_float,
// drops directions from κ ~ 1e4 on: its referee agrees, but the constraint is then not enforced).
// States that are singular for any scalar (κ infinite) do not bound it.
double float_domain(const VariantStudy& float_variant) {
  std::vector<std::pair<double, bool>> points;  // κ, answered
  for (const StatePoint& p : float_variant.states)
    points.emplace_back(p.kappa, p.judged ? p.error() <= kFloatGoal : (p.status & kNotJudged) == 0);
  std::sort(points.begin(), points.end());
  for (const auto& [kappa, answered] : points)
    if (!answered) return kappa;
  return points.empty() ? NAN : INFINITY;
}

// Whether float answered any state at all (float_domain is then more than a bound on nothing).
bool float_answered_any(const VariantStudy& float_variant) {
  return std::any_of(float_variant.states.begin(), float_variant.states.end(),
                     [](const StatePoint& p) { return p.judged && p.error() <= kFloatGoal; });
}

// The sentence for the fastest of `candidates` (the generated double solves of the scene's own
// problem: original policy, its factorisation), with float's domain.
std::string recommend(SceneStudy& study, const std::vector<std::string>& candidates) {
  const VariantStudy* best = nullptr;
  for (const VariantStudy& v : study.variants)
    if (v.note.empty() && std::find(candidates.begin(), candidates.end(), v.name) != candidates.end() &&
        (!best || v.ns_median < best->ns_median))
      best = &v;
  if (!best) return "no generated double variant was measured";
  study.recommended = best->name;
  const std::string timing = format("%.0f", best->ns_median) + " ns median and " + format("%.0f", best->ns_p99) +
                             " ns p99 per solve";
  if (best->all.judged == 0) {
    unsigned raised = 0;
    for (const StatePoint& p : best->states) raised |= (p.status | p.referee_status) & kNotJudged;
    std::string why;
    for (const auto& [bit, name] : {std::pair{solver::status_joint_inertia_singular, "a joint locked (J1)"},
                                    std::pair{solver::status_constraint_rank_deficient, "a constraint direction dropped"},
                                    std::pair{solver::status_not_finite, "a value not finite"}})
      if (raised & bit) why += std::string(why.empty() ? "" : " or ") + name;
    if (why.empty()) why = "a result beyond the scalar's range";
    return best->name + ": no state could be judged: in every one, " + why +
           " for this solver or its referee (sweepgen info lists each joint's mass; a joint without inertia about its "
           "axis is locked at every state), " + timing;
  }
  double kappa_max = 1, ratio = 0;
  for (const StatePoint& p : best->states)
    if (p.judged) {
      kappa_max = std::max(kappa_max, p.kappa);
      ratio = std::max(ratio, p.error() / (std::numeric_limits<double>::epsilon() * p.kappa));
    }
  const FamilyErrors& first = best->families.front();
  std::string sentence = best->name + ": " +
                         (first.judged > 0 ? "error ≤ " + scientific(first.max) + " on " + first.family + " states and "
                                           : "no " + first.family + " state judged; ") +
                         "≤ " + format("%.2g", ratio) + " ε κ on every judged state up to κ = " +
                         format("%.1e", kappa_max) + ", " + timing;
  if (std::isnan(study.float_domain_kappa)) return sentence;
  if (study.float_domain_kappa == 0)
    return sentence + "; float answered none of these states to " + format("%.0e", kFloatGoal) +
           " without dropping a direction";
  if (std::isinf(study.float_domain_kappa)) return sentence + "; float met " + format("%.0e", kFloatGoal) + " on every state";
  return sentence + "; float only where κ < " + format("%.1e", study.float_domain_kappa) + " (error ≤ " +
         format("%.0e", kFloatGoal) + " there)";
}

}  // namespace

SceneStudy study_scene(const scene::Scene& s, const model::Chain& chain, const StudyOptions& options) {
  const auto say = [&](const std::string& what) {
    if (options.progress) options.progress(what);
  };
  SceneStudy study;
  study.name = s.solver;
  study.source = s.path.empty() ? "default scene for " + s.chain.urdf : s.path;
  study.dof = chain.dof();
  study.constraints = s.layout.constraints;
  const std::size_t nc = study.constraints;
  // The layout of what is compiled (report_scene: every result), not of the scene's own outputs.
  const solver::FlatLayout flat = report_scene(s).flat_layout(chain);

  say("states");
  const std::vector<LabelledProblem> states = study_states(s, chain, options, study.singular_note);
  std::vector<Problem> problems;
  // Which path ν takes (C4), per family: ReferenceSolver<double> decides as the generated code.
  solver::ReferenceSolver<double> paths(chain, s.layout, s.solver_options());
  for (const auto& x : states) {
    problems.push_back(x.problem);
    if (study.families.empty() || study.families.back().first != x.kind) {
      study.families.push_back({x.kind, 0});
      study.pivoted_path.push_back(0);
    }
    ++study.families.back().second;
    if (nc > 0) study.pivoted_path.back() += paths.run(x.problem, Policy::original).pivoted_path != 0;
  }

  const TimingOptions timing{options.repetitions}, once{1};
  const ConstraintFactorisation own = s.constraint_factorisation;
  const ConstraintFactorisation other =
      own == ConstraintFactorisation::damped ? ConstraintFactorisation::pivoted_ldlt : ConstraintFactorisation::damped;
  const std::vector<Policy> policies = policies_of(s);
  const CompileProgress quiet{[&](int, const std::string& what) { say(what); }, [](const std::string&) {}};

  std::vector<Measured> measured;
  const auto add = [&](std::string name, std::string solves, std::string scalar, Referee referee, VariantResult r,
                       bool is_referee = false, std::size_t operations = 0) {
    say("measured " + name);
    VariantStudy study;
    study.operations = operations;
    study.keeps_every_direction = referee.factorisation == ConstraintFactorisation::damped;
    study.clamps = referee.policy == Policy::saturate || referee.policy == Policy::saturate_exact;
    study.gives_way_because = gives_way_because(referee.policy, referee.factorisation);
    study.name = std::move(name);
    study.solves = std::move(solves);
    study.scalar = std::move(scalar);
    study.referee = is_referee;
    measured.push_back({std::move(study), std::move(r), referee});
  };
  const auto generated = [&](const char* scalar, Policy p, ConstraintFactorisation f, Isa isa) {
    return "generated " + std::string(scalar) + " " + solver::name(p) +
           (f != own ? " " + policy_name(f) : "") +
           (isa != Isa::baseline ? " " + isa_name(isa) : "");
  };
  const auto what = [&](Policy p, ConstraintFactorisation f, const std::string& compiled_for) {
    const bool refined = solver::refines(s.refinement, nc, p, f);
    return "ACHD " + policy_label(p) + (nc > 0 ? ", " + factorisation_label(f) : "") +
           (refined ? ", refined once (R1)" : "") + ", unrolled, " + compiled_for;
  };

  {
    const CompiledSolver baseline =
        compile_scene_solver(report_scene(s, policies), chain, options.build_dir / "x86-64", options.cxx, quiet);
    for (const Policy p : policies)
      add(generated("double", p, own, Isa::baseline), what(p, own, "-O2 x86-64"), "double", {p, own, "double"},
          measure_generated<double>(baseline.solve_f64_of.at(p), "double", flat, problems, timing), false,
          baseline.operations.at({"double", p}));
    add(generated("float", Policy::original, own, Isa::baseline), what(Policy::original, own, "-O2 x86-64"), "float",
        {Policy::original, own, "float"},
        measure_generated<float>(baseline.solve_f32, "float", flat, problems, timing), false,
        baseline.operations.at({"float", Policy::original}));
  }
  const std::string v3 = generated("double", Policy::original, own, Isa::x86_64_v3);
  if (options.one_compile) {
    study.left_out.push_back(v3);
  } else if (cpu_supports(Isa::x86_64_v3)) {
    const CompiledSolver fast = compile_scene_solver(report_scene(s), chain, options.build_dir / "x86-64-v3",
                                                     options.cxx, quiet, Isa::x86_64_v3);
    add(v3, what(Policy::original, own, "-O3 x86-64-v3 (AVX2, FMA)"), "double", {Policy::original, own, "double"},
        measure_generated<double>(fast.solve_f64_of.at(Policy::original), "double", flat, problems, timing), false,
        fast.operations.at({"double", Policy::original}));
  } else {
    add(v3, "the same for x86-64-v3", "double", {}, {"generated", "double", "this CPU lacks AVX2/FMA/BMI2", {}, {}});
  }
  const std::string other_row = generated("double", Policy::original, other, Isa::baseline);
  if (nc > 0 && options.one_compile) {
    study.left_out.push_back(other_row);
  } else if (nc > 0) {
    const scene::Scene other_scene = with_factorisation(s, other);
    const CompiledSolver compiled = compile_scene_solver(report_scene(other_scene), chain,
                                                         options.build_dir / "other-factorisation", options.cxx, quiet);
    add(other_row, what(Policy::original, other, "-O2 x86-64"), "double", {Policy::original, other, "double"},
        measure_generated<double>(compiled.solve_f64_of.at(Policy::original), "double", flat, problems, timing),
        false, compiled.operations.at({"double", Policy::original}));
  }
  add("reference double", "ReferenceSolver<double>: the same equations, generic loops over the chain (Eigen)",
      "double", {Policy::original, own, "double"}, measure_reference_double(s, chain, problems, timing));
  add("reference binary128", "ReferenceSolver<binary128>: the referee every row is judged against", "binary128",
      {Policy::original, own, "double"}, measure_reference_precise(s, chain, problems, once), true);
  add("KDL", "KDL 1.5 ChainHdSolver_Vereshchagin (Alg. 1, original composition)", "double",
      {Policy::original, own, "double"}, measure_kdl(s, chain, problems, timing));
  measured.back().study.keeps_every_direction = true;
  measured.back().study.gives_way_because = "";
  measured.back().study.unbounded_because =
      "KDL solves E by an SVD with an absolute tolerance, without equilibrating it, and keeps or drops other "
      "directions than the referee near a singularity (docs/stability.md, \"Against KDL\": error ≈ 1 there)";
  add("dense KKT", "M, b, J by Newton–Euler, (n + Nc) KKT system by full-pivot LU (Eigen)", "double",
      {Policy::original, own, "double"}, measure_dense_kkt(s, chain, problems, timing));
  measured.back().study.keeps_every_direction = true;
  measured.back().study.gives_way_because = "";
  measured.back().study.unbounded_because =
      "it solves the (n + Nc) KKT system in the robot's own units, unscaled, whose condition κ does not bound";

  std::map<Referee, std::vector<Truth>> referees;
  for (Measured& m : measured) {
    if (m.result.note.empty() && !m.study.referee && !referees.count(m.referee)) {
      say("referee: binary128, " + std::string(solver::name(m.referee.policy)) + ", " +
          factorisation_label(m.referee.factorisation) + ", " + m.referee.scalar + " tolerances");
      const scene::Scene r = with_factorisation(s, m.referee.factorisation);
      referees[m.referee] = precise_reference(r, chain, problems, with_tolerance_factor(r, 1, epsilon_of(m.referee.scalar)),
                                              m.referee.policy, false);
    }
    summarise(m, m.result.note.empty() && !m.study.referee ? referees.at(m.referee) : std::vector<Truth>{}, states,
              study.families, chain);
    study.variants.push_back(std::move(m.study));
  }
  for (const VariantStudy& v : study.variants)
    if (v.scalar == "float" && v.note.empty()) study.float_domain_kappa = float_answered_any(v) ? float_domain(v) : 0;
  study.recommendation = recommend(study, {generated("double", Policy::original, own, Isa::baseline), v3});
  return study;
}

}  // namespace sweepgen::report
