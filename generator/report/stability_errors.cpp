#include "report/stability_errors.hpp"

#include <utility>

namespace sweepgen::report {

double joint_relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b, const model::Chain& chain,
                            const std::vector<std::vector<Precise>>& also) {
  double worst = 0;
  for (const auto type : {model::JointType::revolute, model::JointType::prismatic}) {
    Precise diff = 0, scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (chain.joints[i + 1].type != type) continue;
      if (!isfinite(a[i])) return INFINITY;
      diff = std::max(diff, abs(a[i] - b[i]));
      scale = std::max(scale, abs(b[i]));
      for (const auto& v : also) scale = std::max(scale, abs(v[i]));
    }
    worst = std::max(worst, static_cast<double>(scale > Precise(0) ? diff / scale : diff));
  }
  return worst;
}

double vector_relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b) {
  Precise diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!isfinite(a[i])) return INFINITY;
    diff = std::max(diff, abs(a[i] - b[i]));
    scale = std::max(scale, abs(b[i]));
  }
  return static_cast<double>(scale > Precise(0) ? diff / scale : diff);
}

StateJudgement judge(const Outcome& outcome, const Truth& truth, const Problem& problem, const model::Chain& chain,
                     double largest) {
  StateJudgement j;
  const std::vector<Precise> tau_ff(problem.tau_ff.data(), problem.tau_ff.data() + problem.tau_ff.size());
  // A result the solve does not return (scene key outputs: an empty vector) is not judged.
  if (!outcome.qdd.empty()) j.qdd = joint_relative_error(outcome.qdd, truth.qdd, chain, {truth.qdd_free});
  if (!outcome.tau_cmd.empty())
    j.tau = joint_relative_error(outcome.tau_cmd, truth.tau_cmd, chain, {tau_ff, truth.tau_constraint_terms});
  if (!outcome.nu.empty()) j.nu = vector_relative_error(outcome.nu, truth.nu);
  j.cond_E = truth.cond_scaled;
  j.rho_D = truth.min_relative_D;
  j.cond_M = truth.cond_M;
  j.constraint_residual = static_cast<double>(constraint_residual(outcome, problem));
  j.status = outcome.status;
  j.exact_status = truth.status;
  for (const auto* v : {&outcome.qdd, &outcome.tau_cmd, &outcome.nu})
    for (const Precise& x : *v) j.finite = j.finite && isfinite(x);
  for (const auto& [returned, exact] : {std::pair{&outcome.qdd, &truth.qdd}, std::pair{&outcome.tau_cmd, &truth.tau_cmd},
                                        std::pair{&outcome.nu, &truth.nu}})
    for (const Precise& x : *exact) j.representable = j.representable && (returned->empty() || abs(x) <= Precise(largest));
  return j;
}

}  // namespace sweepgen::report
