// `sweepgen report`: one scene studied. Its state families (extreme_states.hpp) go through every
// variant of a solver the scene can use, side by side, each judged state by state against the
// binary128 referee of the problem it solves (stability_errors.hpp), and timed call by call
// (README, "sweepgen report").
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "model/chain.hpp"
#include "scene/scene.hpp"

namespace sweepgen::report {

struct StudyOptions {
  std::size_t states_per_family = 40;  // per random family; the near-singular sweep has 6 per δ
  int repetitions = 10;                // timed passes over the states (binary128: 1)
  unsigned long long seed = 1;
  std::string cxx = "c++";
  std::filesystem::path build_dir;  // the scene's generated code: build_dir/<variant>/
  // --quick: one compile per scene, the x86-64 baseline with every policy; the rows that need a
  // compile of their own (x86-64-v3, the other factorisation) are left out (SceneStudy::left_out).
  bool one_compile = false;
  std::function<void(const std::string& what)> progress;  // one line per step
};

// Error statistics of one variant on one family of states (or on all of them).
struct FamilyErrors {
  std::string family;
  std::size_t states = 0;  // in the family
  // States where neither the variant nor its referee dropped a direction, locked a joint or
  // returned a value that is not finite (a saturating policy's clamp does not count): the errors
  // are rounding only there; the quantiles run over these.
  std::size_t judged = 0;
  double median = NAN, p99 = NAN, max = NAN;  // StateJudgement::error() over the judged states
  double max_residual = NAN;                  // constraint_residual over the judged states
  std::size_t status_raised = 0;              // states where the variant raised a status bit
};

// One judged state of one variant.
struct StatePoint {
  std::string family;
  double kappa = 1;                    // StateJudgement::kappa()
  double qdd = 0, tau = 0, nu = 0;     // StateJudgement's relative errors
  double residual = 0;                 // constraint_residual
  unsigned status = 0, referee_status = 0;
  bool judged = false;                 // counted in FamilyErrors::judged
  double error() const { return std::max({qdd, tau, nu}); }
};

struct VariantStudy {
  std::string name;    // e.g. "generated double original x86-64"
  std::string solves;  // what it solves and how, one line
  std::string scalar;  // double, float, binary128
  std::string note;    // why it has no numbers (empty when measured)
  bool referee = false;  // the binary128 referee itself: timed, error 0 by definition
  // Solves with every direction, dropping none (KDL, the dense KKT, a damped factorisation).
  bool keeps_every_direction = false;
  bool clamps = false;  // a saturating policy: clamps torques at their effort limits
  // Why this row does not meet the constraint to rounding, by design ("": it does).
  std::string gives_way_because;
  // Why the stability suite's bound of 100 ε κ does not hold for this row ("": it holds, the
  // project's own solvers).
  std::string unbounded_because;
  double ns_median = NAN, ns_p99 = NAN, ns_max = NAN;  // per call, after a warm-up pass
  std::size_t operations = 0;  // generated rows: the generator's operation count of one full solve
  std::vector<FamilyErrors> families;                  // SceneStudy::families order
  FamilyErrors all;                                    // every family together
  std::vector<StatePoint> states;                      // every state, in study order
};

struct SceneStudy {
  std::string name;    // the scene's solver namespace
  std::string source;  // the scene file (or what the scene was made from)
  std::size_t dof = 0, constraints = 0;
  std::vector<std::pair<std::string, std::size_t>> families;  // name, states
  std::vector<std::size_t> pivoted_path;  // per family: states whose ν took the pivoted path (C4)
  std::string singular_note;  // where the near-singular sweep starts, or why there is none
  std::vector<VariantStudy> variants;
  // Rows StudyOptions::one_compile left out, each needing a compile of its own.
  std::vector<std::string> left_out;
  // Generated float answers every state below this κ (NaN: no float row; 0: it answered none).
  double float_domain_kappa = NAN;
  std::string recommendation;       // one sentence
  std::string recommended;          // the row it recommends ("" if none)
};

// The accuracy a float solve has to reach for its state to count as inside float's domain (it
// must also keep every direction: study.cpp, float_domain).
constexpr double kFloatGoal = 1e-4;

// Studies one scene; `label` names it in progress lines. Throws io::IoError when the compiler or
// dlopen() fails.
SceneStudy study_scene(const scene::Scene& s, const model::Chain& chain, const StudyOptions& options);

}  // namespace sweepgen::report
